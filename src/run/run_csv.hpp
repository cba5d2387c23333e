#pragma once
// The per-step CSV files of a scene run (history.csv, newton.csv): written row by row at full precision;
// after a restart, what came before the checkpoint stays and what a stopped run wrote after it goes.
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"

namespace mpm {

/// The lines of a CSV whose first column is a step number: the header and the rows up to `step` (none when
/// the file does not exist).
inline std::vector<std::string> rows_until(const std::filesystem::path& file, std::int64_t step) {
  std::vector<std::string> kept;
  std::ifstream is(file);
  for (std::string line; std::getline(is, line);) {
    if (!kept.empty() && std::stoll(line.substr(0, line.find(','))) > step) break;
    kept.push_back(line);
  }
  return kept;
}

class CsvFile {
 public:
  /// A fresh file holding `header`, or after a restart the lines up to the checkpoint's `step` (the header
  /// alone when the earlier file is gone).
  void open(const std::filesystem::path& file, const std::string& header, bool restart, std::int64_t step) {
    file_ = file;
    const std::vector<std::string> kept = restart ? rows_until(file, step) : std::vector<std::string>{};
    os_.open(file, std::ios::trunc);
    if (!os_) throw InputError("--out: cannot write " + file.string());
    os_.precision(17);
    if (kept.empty()) os_ << header << '\n';
    for (const std::string& line : kept) os_ << line << '\n';
  }
  bool is_open() const { return os_.is_open(); }

  /// The stream to write a row's cells to; end_row() ends it.
  std::ostream& row() { return os_; }
  void end_row() {
    os_ << '\n';
    if (!os_) failed();
  }

  void flush() {
    os_.flush();
    if (!os_) failed();
  }
  void close() {
    flush();
    os_.close();
  }

 private:
  [[noreturn]] void failed() const {
    throw OutputError("cannot write " + file_.string() + ": " +
                      (errno ? std::strerror(errno) : "write failed"));
  }

  std::filesystem::path file_;
  std::ofstream os_;
};

}  // namespace mpm

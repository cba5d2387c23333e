#pragma once
// newton.csv ([output] newton_log = "on", implicit runs): ||F|| at every Newton iterate of every try at every
// step, the tries halved after a failed solve included, so that the residual histories of Sulsky & Kaul 2004,
// Figs 5 and 9, can be drawn.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/implicit/simulation.hpp"
#include "run_csv.hpp"

namespace mpm {

class NewtonLog {
 public:
  NewtonLog() = default;
  explicit NewtonLog(std::filesystem::path file) : file_(std::move(file)) {}

  /// A fresh file, or after a restart the rows up to the checkpoint's step.
  void open(const std::filesystem::path& file, bool restart, std::int64_t step) {
    file_ = file;
    rewrite(restart ? rows_until(file, step) : std::vector<std::string>{});
  }
  bool is_open() const { return os_.is_open(); }

  /// Cut the file back to the rows up to `step` and close it (a restart that does not log further).
  void trim(std::int64_t step) {
    rewrite(rows_until(file_, step));
    flush();
    os_.close();
  }

  /// The tries at step `step` (1 for the first step): attempt 0 is the first, each later one half the step before.
  void write(std::int64_t step, const std::vector<NewtonAttempt>& attempts) {
    for (std::size_t a = 0; a < attempts.size(); ++a)
      for (std::size_t k = 0; k < attempts[a].residual_norms.size(); ++k)
        os_ << step << ',' << a << ',' << attempts[a].dt << ',' << k << ',' << attempts[a].residual_norms[k] << '\n';
    if (!os_) failed();
  }

  void flush() {
    os_.flush();
    if (!os_) failed();
  }

 private:
  /// Start the file afresh with these lines, or with the header when there are none.
  void rewrite(const std::vector<std::string>& kept) {
    os_.open(file_, std::ios::trunc);
    if (!os_) throw InputError("--out: cannot write " + file_.string());
    os_.precision(17);
    if (kept.empty()) os_ << "step,attempt,dt,iteration,residual_norm\n";
    for (const std::string& line : kept) os_ << line << '\n';
  }

  [[noreturn]] void failed() const {
    throw OutputError("cannot write " + file_.string() + ": " + (errno ? std::strerror(errno) : "write failed"));
  }

  std::filesystem::path file_;
  std::ofstream os_;
};

}  // namespace mpm

#pragma once
// The per-step CSV files of a scene run (history.csv, newton.csv) after a restart: what came before the
// checkpoint stays, what a stopped run wrote after it goes.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace mpm {

/// The lines of a CSV whose first column is a step number: the header and the rows up to `step` (none when the
/// file does not exist).
inline std::vector<std::string> rows_until(const std::filesystem::path& file, std::int64_t step) {
  std::vector<std::string> kept;
  std::ifstream is(file);
  for (std::string line; std::getline(is, line);) {
    if (!kept.empty() && std::stoll(line.substr(0, line.find(','))) > step) break;
    kept.push_back(line);
  }
  return kept;
}

}  // namespace mpm

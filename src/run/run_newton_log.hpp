#pragma once
// newton.csv ([output] newton_log = "on", implicit runs): ||F|| at every Newton iterate of every try at every
// step, the tries halved after a failed solve included, so that the residual histories of Sulsky & Kaul 2004,
// Figs 5 and 9, can be drawn.
#include <filesystem>
#include <vector>

#include "mpm/implicit/simulation.hpp"
#include "run_csv.hpp"

namespace mpm {

class NewtonLog {
 public:
  static constexpr const char* header = "step,attempt,dt,iteration,residual_norm";

  /// A fresh file, or after a restart the rows up to the checkpoint's step.
  void open(const std::filesystem::path& file, bool restart, std::int64_t step) {
    csv_.open(file, header, restart, step);
  }
  bool is_open() const { return csv_.is_open(); }

  /// Cut an earlier run's file back to the rows up to `step` (a restart that does not log further).
  static void trim(const std::filesystem::path& file, std::int64_t step) {
    NewtonLog log;
    log.open(file, true, step);
    log.csv_.close();
  }

  /// The tries at step `step` (1 for the first step): attempt 0 is the first, each later one half the step
  /// before.
  void write(std::int64_t step, const std::vector<NewtonAttempt>& attempts) {
    for (std::size_t a = 0; a < attempts.size(); ++a)
      for (std::size_t k = 0; k < attempts[a].residual_norms.size(); ++k) {
        csv_.row() << step << ',' << a << ',' << attempts[a].dt << ',' << k << ','
                   << attempts[a].residual_norms[k];
        csv_.end_row();
      }
  }

  void flush() { csv_.flush(); }

 private:
  CsvFile csv_;
};

}  // namespace mpm

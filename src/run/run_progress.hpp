#pragma once
// Progress of a scene run on stderr.
#include <chrono>
#include <cstdint>
#include <cstdio>

#include "mpm/core/types.hpp"

namespace mpm {

/// Progress on stderr for runs longer than about two seconds: percent, step, time, steps per second, ETA.
class Progress {
 public:
  Progress(bool quiet, Real t0, Real t_end)
      : quiet_(quiet), t0_(t0), t_end_(t_end), start_(std::chrono::steady_clock::now()), last_(start_) {}
  void update(std::int64_t step, Real t) {
    if (quiet_) return;
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (elapsed < 2 || std::chrono::duration<double>(now - last_).count() < 0.5) return;
    last_ = now;
    const double fraction = (t - t0_) / (t_end_ - t0_);
    const double rate = static_cast<double>(step - first_step_) / elapsed;
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    std::fprintf(stderr, "\r%5.1f%%  step %lld  t = %.6g s  %.0f steps/s  ETA %.0f s   ", 100 * t / t_end_,
                 static_cast<long long>(step), t, rate, eta);
    printed_ = true;
  }
  void start_at(std::int64_t step) { first_step_ = step; }
  ~Progress() {
    if (printed_) std::fprintf(stderr, "\n");
  }

 private:
  bool quiet_;
  Real t0_, t_end_;
  std::chrono::steady_clock::time_point start_, last_;
  std::int64_t first_step_ = 0;
  bool printed_ = false;
};

}  // namespace mpm

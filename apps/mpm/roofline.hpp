#pragma once
// The machine's limits for `mpm bench --roofline` (docs/performance.md, "Roofline").

namespace mpm::app {

struct Roofline {
  int threads = 1;
  double triad_bytes_per_second = 0;  ///< memory bandwidth, STREAM triad (24 bytes an element)
  double fused_flops_per_second = 0;  ///< arithmetic peak with fused multiply-adds
  double separate_flops_per_second =
      0;  ///< arithmetic peak with separate multiplies and adds, as the code compiles
};

/// Measure the limits with the pool's threads (set_num_threads).
Roofline measure_roofline();

}  // namespace mpm::app

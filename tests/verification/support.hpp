#pragma once
// Helpers of the verification tests.
#include <algorithm>

namespace mpm::testing {

/// The smallest and largest of the values added.
struct Spread {
  double min = 1e300, max = -1e300;
  void add(double v) {
    min = std::min(min, v);
    max = std::max(max, v);
  }
};

}  // namespace mpm::testing

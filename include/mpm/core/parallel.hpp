#pragma once
/// The one parallel loop helper: kernels are written as loop bodies over an index range.
#include <cstddef>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace mpm {

/// Run fn(i) for i in [0, n) on all threads; loops shorter than `min_parallel` run on the calling thread
/// (starting threads costs more than small loops gain). Bodies must not depend on which thread runs which
/// index.
template <class Fn>
void parallel_for(std::ptrdiff_t n, Fn&& fn, std::ptrdiff_t min_parallel = 1024) {
#pragma omp parallel for schedule(static) if (n >= min_parallel)
  for (std::ptrdiff_t i = 0; i < n; ++i) fn(i);
}

/// Set the number of threads used by parallel_for (0 keeps the default).
inline void set_num_threads(int n) {
#ifdef _OPENMP
  if (n > 0) omp_set_num_threads(n);
#else
  (void)n;
#endif
}

/// The number of threads parallel_for will use.
inline int num_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

}  // namespace mpm

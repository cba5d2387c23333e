// `mpm bench --roofline`: the two limits of this machine a time step can meet, measured with the pool's
// threads.
#include "roofline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>
#ifdef __FMA__
#include <immintrin.h>
#endif

#include "mpm/core/parallel.hpp"

namespace mpm::app {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// STREAM's triad a = b + s c (McCalpin 1995) over arrays far larger than the caches: the best of `repeat`
/// sweeps, counted as STREAM counts it (24 bytes an element: two loads and a store; the write-allocate read
/// of a, which the hardware adds, is not counted).
double triad_bytes_per_second(std::ptrdiff_t n, int repeat) {
  std::vector<double> a(static_cast<std::size_t>(n)), b(a.size()), c(a.size());
  parallel_for(n, [&](std::ptrdiff_t i) {
    a[i] = 0;
    b[i] = 1;
    c[i] = 2;
  });
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    parallel_for(n, [&](std::ptrdiff_t i) { a[i] = b[i] + 3.0 * c[i]; });
    best = std::min(best, seconds_since(t0));
  }
  if (a[static_cast<std::size_t>(n / 2)] != 7.0) return 0;  // keeps the sweeps; 1 + 3 x 2 exactly
  return 24.0 * static_cast<double>(n) / best;
}

/// Four doubles, one 256-bit register (GCC's and Clang's vector extension).
using Quad = double __attribute__((vector_size(32)));

template <bool fused>
[[gnu::always_inline]] inline Quad chain_step(Quad x, Quad a, Quad b) {
  if constexpr (fused) {
#ifdef __FMA__
    return _mm256_fmadd_pd(x, a, b);
#else  // no fused instruction on this target: the library's fma, lane by lane
    Quad r;
    for (int l = 0; l < 4; ++l) r[l] = std::fma(x[l], a[l], b[l]);
    return r;
#endif
  } else {
    return x * a + b;
  }
}

/// 8 independent chains of 4 lanes of x = x a + b on each thread, in registers: the arithmetic peak on
/// 256-bit vectors, the width the code is compiled for. `fused` uses one fused multiply-add per step (2 flops
/// in one instruction), else a multiply and an add, which is what the project's code compiles to
/// (-ffp-contract=off keeps IEEE rounding of every product).
template <bool fused>
double chains(long iterations) {
  const Quad a = {0.999999999, 0.999999998, 0.999999997, 0.999999996}, b = {1e-9, 2e-9, 3e-9, 4e-9};
  Quad x0 = a, x1 = a + b, x2 = a + 2 * b, x3 = a + 3 * b, x4 = a + 4 * b, x5 = a + 5 * b, x6 = a + 6 * b,
       x7 = a + 7 * b;
  for (long k = 0; k < iterations; ++k) {
    x0 = chain_step<fused>(x0, a, b);
    x1 = chain_step<fused>(x1, a, b);
    x2 = chain_step<fused>(x2, a, b);
    x3 = chain_step<fused>(x3, a, b);
    x4 = chain_step<fused>(x4, a, b);
    x5 = chain_step<fused>(x5, a, b);
    x6 = chain_step<fused>(x6, a, b);
    x7 = chain_step<fused>(x7, a, b);
  }
  const Quad sum = x0 + x1 + x2 + x3 + x4 + x5 + x6 + x7;
  return sum[0] + sum[1] + sum[2] + sum[3];
}

template <bool fused>
double flops_per_second(long iterations, int repeat) {
  const int threads = num_threads();
  std::vector<double> sink(static_cast<std::size_t>(threads));
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    parallel_for(
        threads, [&](std::ptrdiff_t t) { sink[static_cast<std::size_t>(t)] = chains<fused>(iterations); }, 1);
    best = std::min(best, seconds_since(t0));
  }
  double check = 0;
  for (double s : sink) check += s;
  if (!std::isfinite(check)) return 0;
  return 2.0 * 32.0 * static_cast<double>(iterations) * threads / best;
}

}  // namespace

Roofline measure_roofline() {
  Roofline r;
  r.threads = num_threads();
  r.triad_bytes_per_second = triad_bytes_per_second(std::ptrdiff_t{1} << 25, 10);  // 3 x 256 MiB
  r.fused_flops_per_second = flops_per_second<true>(4'000'000, 5);
  r.separate_flops_per_second = flops_per_second<false>(4'000'000, 5);
  return r;
}

}  // namespace mpm::app

#pragma once
/// What both engines sum over their particles, written once: the sums reported in history.csv, the same bits
/// for any division and thread count, and the power of the loads over a step.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mpm/core/exact_sum.hpp"
#include "mpm/core/types.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// The sums over all the particles, every rank's, of the N values fn(i) gives particle i: the particles of
/// each run of equal group(i) in storage order are added from zero in that order, and the runs' sums exactly
/// (ExactSum) over runs and ranks. When each run holds one tile's particles in id order (the explicit
/// engine's settled particles), the result is the same bits whatever the division of the grid and the thread
/// count.
template <std::size_t N, class Group, class Fn>
std::array<Real, N> exact_particle_sum(std::size_t n, Group&& group, Fn&& fn, const Communicator& comm) {
  std::array<ExactSum, N> total;
  for (std::size_t i = 0; i < n;) {
    std::array<Real, N> partial{};
    const std::int32_t g = group(i);
    for (; i < n && group(i) == g; ++i) {
      const std::array<Real, N> v = fn(i);
      for (std::size_t k = 0; k < N; ++k) partial[k] += v[k];
    }
    for (std::size_t k = 0; k < N; ++k) total[k].add(partial[k]);
  }
  std::vector<std::int64_t> integers;
  for (const ExactSum& e : total) {
    const std::vector<std::int64_t> mine = e.integers();
    integers.insert(integers.end(), mine.begin(), mine.end());
  }
  comm.sum(integers);
  std::array<Real, N> out;
  for (std::size_t k = 0; k < N; ++k) {
    const auto first = integers.begin() + static_cast<std::ptrdiff_t>(k * ExactSum::integer_count);
    out[k] = ExactSum::from_integers({first, first + static_cast<std::ptrdiff_t>(ExactSum::integer_count)})
                 .value();
  }
  return out;
}

/// The power of gravity g and the body force b_p on particle i over a step [W]: m_p (g + b_p) . (v_p^n +
/// v_p^{n+1}) / 2, the trapezoidal rule on its velocities before and after (b empty: gravity alone).
template <int Dim>
Real particle_load_power(const ParticleSet<Dim>& p, std::size_t i, const Vec<Dim>& gravity,
                         const std::vector<Vec<Dim>>& b, const std::vector<Vec<Dim>>& v_before) {
  const Vec<Dim> load = b.empty() ? gravity : Vec<Dim>(gravity + b[i]);
  return p.m[i] * load.dot(0.5 * (v_before[i] + p.v[i]));
}

}  // namespace mpm

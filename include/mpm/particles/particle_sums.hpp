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

/// Visit the runs of equal group(i) among particles 0 .. n - 1 in storage order: visit(begin, end).
template <class Group, class Visit>
void for_each_run(std::size_t n, Group&& group, Visit&& visit) {
  for (std::size_t i = 0; i < n;) {
    const std::size_t begin = i;
    const std::int32_t g = group(i);
    while (i < n && group(i) == g) ++i;
    visit(begin, i);
  }
}

/// The sums over all the particles, every rank's, of the N values fn(i) gives particle i, the particles
/// visited in runs by for_each(visit) (visit(begin, end)): each run's particles are added from zero in order,
/// and the runs' sums exactly (ExactSum) over runs and ranks.
template <std::size_t N, class ForEachRun, class Fn>
std::array<Real, N> exact_run_sum(ForEachRun&& for_each, Fn&& fn, const Communicator& comm) {
  std::array<ExactSum, N> total;
  for_each([&](std::size_t begin, std::size_t end) {
    std::array<Real, N> partial{};
    for (std::size_t i = begin; i < end; ++i) {
      const std::array<Real, N> v = fn(i);
      for (std::size_t k = 0; k < N; ++k) partial[k] += v[k];
    }
    for (std::size_t k = 0; k < N; ++k) total[k].add(partial[k]);
  });
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

/// exact_run_sum over the runs of equal group(i) in storage order. When each run holds one tile's particles
/// in id order (the explicit engine's settled particles), the result is the same bits whatever the division
/// of the grid and the thread count.
template <std::size_t N, class Group, class Fn>
std::array<Real, N> exact_particle_sum(std::size_t n, Group&& group, Fn&& fn, const Communicator& comm) {
  return exact_run_sum<N>([&](const auto& visit) { for_each_run(n, group, visit); }, fn, comm);
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

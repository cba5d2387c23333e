#pragma once
/// Displacement error norms over particles and time steps. Wallstedt & Guilkey 2008, Eq. (64), Eq. (65).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "mpm/core/types.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// Accumulates samples of an error: here delta_p = |(x_p - X_p) - u_exact(X_p, t)| (Wallstedt & Guilkey 2008,
/// Eq. (64)). L_inf is the maximum over all particles and all recorded steps (Wallstedt & Guilkey 2008,
/// Eq. (65)); L1 and L2 weight every particle-step sample equally: L1 = mean delta_p, L2 = sqrt(mean
/// delta_p^2). A particle's displacement error |(x - X) - u(X, t)|; on a solution periodic with unit period
/// along each axis (Exact::periodic), that of the nearest image.
template <int Dim, class Exact>
Real displacement_error(const Exact& exact, const Vec<Dim>& x, const Vec<Dim>& X, Real t) {
  Vec<Dim> e = (x - X) - exact.displacement(X, t);
  if constexpr (requires { Exact::periodic; })
    for (int d = 0; d < Dim; ++d) e[d] -= std::round(e[d]);
  return e.norm();
}

struct ErrorNorms {
  Real linf = 0;
  Real sum = 0;
  Real sum_sq = 0;
  std::int64_t samples = 0;

  template <int Dim, class Exact>
  void record(const ParticleSet<Dim>& p, Real t, const Exact& exact) {
    for (std::size_t i = 0; i < p.size(); ++i) add(displacement_error<Dim>(exact, p.x[i], p.X[i], t));
  }
  /// One sample.
  void add(Real delta) {
    linf = std::max(linf, delta);
    sum += delta;
    sum_sq += delta * delta;
    ++samples;
  }
  /// The samples of one step over every rank: their largest, sum, sum of squares and count.
  void add_sums(Real largest, Real step_sum, Real step_sum_sq, std::int64_t count) {
    linf = std::max(linf, largest);
    sum += step_sum;
    sum_sq += step_sum_sq;
    samples += count;
  }
  Real l1() const { return samples ? sum / static_cast<Real>(samples) : 0; }
  Real l2() const { return samples ? std::sqrt(sum_sq / static_cast<Real>(samples)) : 0; }
};

}  // namespace mpm

#pragma once
/// The explicit time step, written once: the explicit engine takes it every step, the implicit engine as its
/// reference step, and the scene's budget estimates it before a run.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// The CFL condition dt = cfl h / c_max [s] on a grid of cell width h [m], c_max the fastest signal [m/s]
/// (Wallstedt & Guilkey 2008, Sec. 4: the dilatational wave speed plus the particle speed).
inline Real cfl_step(Real cfl, Real h, Real fastest_signal) {
  return cfl * h / fastest_signal;
}

/// The fastest signal of the particles, max_p (c_p + |v_p|) [m/s]: c_p the dilatational wave speed of the
/// particle's material at its volume ratio V / V0 (and its stress, for the laws whose stiffness depends on
/// it; without a material state, unstressed), |v_p| its speed. A maximum, so the same bits for any thread
/// count.
template <int Dim>
Real fastest_signal(const ParticleSet<Dim>& p, const std::vector<Material>& materials) {
  const SymTensor<3> unstressed{};
  const bool stressed = !p.state.empty();
  return parallel_reduce(
      static_cast<std::ptrdiff_t>(p.size()), Real{0},
      [&](std::ptrdiff_t i) {
        return wave_speed(materials[p.material[i]], p.V[i] / p.V0[i],
                          stressed ? p.state.sigma[i] : unstressed) +
               p.v[i].norm();
      },
      [](Real a, Real b) { return std::max(a, b); });
}

}  // namespace mpm

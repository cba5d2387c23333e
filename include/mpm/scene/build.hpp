#pragma once
/// Turning a scene into the engine's inputs: the simulation spec and the seeded particles.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "mpm/explicit/spec.hpp"
#include "mpm/implicit/spec.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {

/// Grid, boundary conditions, integrator, kernel, materials, gravity, and the body force (the scene's
/// expression plus box-face tractions carried by the outermost particle layer).
template <int Dim>
SimulationSpec<Dim> make_spec(const Scene& scene);

/// The implicit integrator's inputs: grid, faces, [implicit] settings, rate-form materials, rigid bodies,
/// gravity.
template <int Dim>
ImplicitSpec<Dim> make_implicit_spec(const Scene& scene);

/// Particles of every body in order: lattice shapes with ppc particles per cell per axis aligned to the
/// shape's lower corner, or the rows of a particle file; initial velocity, displacement and F as given.
/// Throws InputError naming the body when it yields no particles, a particle lies outside the grid, or its
/// fastest particle overflows the time step or the step budget (check_initial_speed).
template <int Dim>
ParticleSet<Dim> seed_bodies(const Scene& scene);

/// The speed of the fastest of `v` [m/s]: |v| without overflow (finite up to about 1.8e308), infinite where
/// one overflows or is not a number.
template <int Dim>
Real fastest_speed(std::span<const Vec<Dim>> v) {
  Real speed = 0;
  for (const Vec<Dim>& vi : v) {
    const Real s = vi.stableNorm();
    speed = std::isfinite(s) ? std::max(speed, s) : std::numeric_limits<Real>::infinity();
  }
  return speed;
}

}  // namespace mpm

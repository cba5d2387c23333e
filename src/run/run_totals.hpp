#pragma once
// What a scene run reports of its particles as a whole: energies and momentum, and when a damped run settled.
#include <cstdint>
#include <nlohmann/json.hpp>

#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// When the kinetic energy of a run settled: the first history time from which it stayed below 1e-4 of the
/// largest it reached (since the start or the restart). Reported for damped runs, which come to rest.
struct Settling {
  static constexpr Real fraction = 1e-4;
  Real largest = 0, since = 0;
  bool settled = false;
  void observe(Real time, Real kinetic) {
    if (kinetic > largest) largest = kinetic;
    const bool below = kinetic <= fraction * largest;
    if (below && !settled) since = time;
    settled = below;
  }
  nlohmann::json report() const {
    nlohmann::json j{{"fraction", fraction}, {"largest_kinetic_energy", largest}, {"settled", settled}};
    if (settled) j["time"] = since;
    return j;
  }
};

/// The particles whose cpGIMP domains the stencil bounds (ParticleSet::half_length_bounded) after each step:
/// the step they first appeared at and how many, and the most at once (since the start or the restart).
struct BoundedDomains {
  std::int64_t first_step = -1, first_count = 0, most = 0;
  Real first_time = 0;
  /// The count after a step; true at the first step with any.
  bool observe(std::int64_t step, Real time, std::int64_t count) {
    if (count > most) most = count;
    if (count == 0 || first_step >= 0) return false;
    first_step = step, first_time = time, first_count = count;
    return true;
  }
  nlohmann::json report() const {
    return {{"first_step", first_step},
            {"first_time", first_time},
            {"first_particles", first_count},
            {"most_particles", most}};
  }
};

/// This rank's particles whose half-lengths are bounded (ParticleSet::half_length_bounded).
template <int Dim>
std::int64_t bounded_half_lengths(const ParticleSet<Dim>& p) {
  if (p.half_lengths != HalfLengths::deformed) return 0;
  return parallel_reduce(
      static_cast<std::ptrdiff_t>(p.size()), std::int64_t{0},
      [&](std::ptrdiff_t i) -> std::int64_t { return p.half_length_bounded(static_cast<std::size_t>(i)); },
      [](std::int64_t a, std::int64_t b) { return a + b; });
}

/// Energies and momentum of the particles: kinetic 1/2 m v^2 and the engine's strain (or internal) energy.
template <int Dim>
struct Totals {
  Real kinetic = 0, strain = 0;
  Vec<Dim> momentum = Vec<Dim>::Zero();
};

}  // namespace mpm

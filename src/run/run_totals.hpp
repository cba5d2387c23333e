#pragma once
// What a scene run reports of its particles as a whole: energies and momentum, and when a damped run settled.
#include <nlohmann/json.hpp>

#include "mpm/core/types.hpp"

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

/// Energies and momentum of the particles: kinetic 1/2 m v^2 and the engine's strain (or internal) energy.
template <int Dim>
struct Totals {
  Real kinetic = 0, strain = 0;
  Vec<Dim> momentum = Vec<Dim>::Zero();
};

}  // namespace mpm

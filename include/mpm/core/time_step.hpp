#pragma once
/// The guard both engines put on each step's dt: a run whose step no longer advances the time stops.
#include <cstdint>
#include <cstdio>

#include "mpm/core/errors.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

/// Throws SimulationFailure when `dt`, the step about to be taken from `time` (`steps` taken so far), is not
/// positive or too small to change `time`: a particle's speed or a wave speed overflowed or grew without
/// bound (dt = CFL h / inf = 0), and the run would otherwise repeat the same time forever.
inline void check_step_advances(std::int64_t steps, Real time, Real dt) {
  if (dt > 0 && time + dt > time) return;
  char text[256];
  std::snprintf(
      text, sizeof text,
      "step %lld, t = %.9g s: the time step dt = %.3g s no longer advances the time (a particle's speed "
      "or a wave speed overflowed or grew without bound)",
      static_cast<long long>(steps + 1), time, dt);
  throw SimulationFailure(text);
}

}  // namespace mpm

#include "mpm/explicit/spec.hpp"

#include <array>
#include <cmath>
#include <sstream>

#include "mpm/core/errors.hpp"

namespace mpm {

namespace {
constexpr std::array<std::string_view, 4> integrator_names{"usf", "usl", "cd", "musl"};
}  // namespace

Integrator parse_integrator(std::string_view name, std::string_view key) {
  return parse_name<Integrator>(integrator_names, name, key);
}

std::string_view to_string(Integrator i) {
  return integrator_names[static_cast<std::size_t>(i)];
}
template <int Dim>
void validate(const SimulationSpec<Dim>& s) {
  validate_model<Dim>(s, "");
  validate(s.contact);
  if (measures_gaps(s.contact))
    for (const FaceCondition<Dim>& f : s.boundary.faces)
      require(f.type != FaceType::periodic,
              "contact: the gap of mass centres is not measured across periodic faces");
  for (const RigidBody<Dim>& b : s.rigid_bodies)
    require(b.friction < 0 || std::isfinite(b.friction),
            "rigid body '" + b.name + "': friction must be finite");
  if (s.dt > 0) {
    require(std::isfinite(s.dt), "dt: must be finite");
  } else {
    require(s.dt == 0, "dt: must be positive (or 0 to use the CFL number)");
    require(s.cfl > 0 && s.cfl <= 1, "cfl: expected a number in (0, 1]");
  }
  require(s.rebalance_above >= 1, "rebalance_above: expected a ratio of at least 1");
  require(s.rebalance_interval >= 1, "rebalance_interval: expected at least 1 step");
  require(!s.half_step_velocity_given || s.integrator == Integrator::cd || s.integrator == Integrator::musl,
          "half_step_velocity_given: only CD and UVF-MPM (musl) start from half-step velocities");
  require(s.local_damping >= 0 && s.local_damping < 1, "local_damping: expected a number in [0, 1)");
}

template void validate<1>(const SimulationSpec<1>&);
template void validate<2>(const SimulationSpec<2>&);
template void validate<3>(const SimulationSpec<3>&);

}  // namespace mpm

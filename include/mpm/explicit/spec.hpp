#pragma once
/// Plain parameter structs describing an explicit simulation, validated in full before anything is built.
#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/contact/multi_field.hpp"
#include "mpm/core/types.hpp"
#include "mpm/model/spec.hpp"

namespace mpm {

/// Explicit time integrators of Wallstedt & Guilkey 2008: update stress first (USF) or last (USL), centered
/// difference (CD) and the update-velocity-first / modified USL variant (UVF-MPM, "musl").
enum class Integrator { usf, usl, cd, musl };

/// An explicit simulation: the model and the explicit integrator's settings.
template <int Dim>
struct SimulationSpec : ModelSpec<Dim> {
  Integrator integrator = Integrator::usl;
  /// Velocity fields and their contact (one field by default): each particle projects to field
  /// ParticleSet::field.
  ContactSpec contact;
  /// Local non-viscous damping alpha in [0, 1) of the grid update (node_update; Cundall 1987): 0 is none. It
  /// brings a body quasi-statically to equilibrium (a gravity ramp, a slope), and it is not
  /// energy-conserving.
  Real local_damping = 0;
  Real dt = 0;   ///< fixed time step [s], or 0 to use the CFL number
  Real cfl = 0;  ///< dt = cfl h / max_p (c_p + |v_p|) when dt == 0
  /// CD and UVF-MPM: the particle velocities given are v^{-1/2}, so the first grid acceleration is not halved
  /// (Wallstedt & Guilkey 2008, Sec. 4: the start from exact half-step data); false starts from v^0.
  bool half_step_velocity_given = false;
  /// USL and CD with the linear kernel: move and deform particles with the re-projected velocity on nodes
  /// that carry less than a quarter of the lightest particle's mass (Sulsky & Kaul 2004, Eq. (3.2.7)); false
  /// runs the papers' algorithms unchanged (Wallstedt & Guilkey 2008, Eq. (37), Eq. (38), Eq. (39)). Scenes
  /// default to true.
  bool reproject_light_nodes = false;
  /// Account the power of gravity and the body force in each step (Simulation::load_power), for an energy
  /// balance; scenes do, the benchmark does not.
  bool account_load_power = false;
  /// Divided between ranks: the grid is divided again when the rank holding the most particles holds more
  /// than this many times the mean (checked after every step, at most once every rebalance_interval steps).
  Real rebalance_above = 1.2;
  int rebalance_interval = 10;
};

/// Parse a name; throws InputError naming `key` and the expected values.
Integrator parse_integrator(std::string_view name, std::string_view key = "integrator");
std::string_view to_string(Integrator i);

/// Throw InputError with a clear message for the first invalid field.
template <int Dim>
void validate(const SimulationSpec<Dim>& spec);

}  // namespace mpm

#pragma once
/// Plain parameter structs describing an explicit simulation, validated in full before anything is built.
#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_body.hpp"
#include "mpm/boundary/surface_loads.hpp"
#include "mpm/contact/multi_field.hpp"
#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "mpm/transfer/passes.hpp"

namespace mpm {

/// Explicit time integrators of Wallstedt & Guilkey 2008: update stress first (USF) or last (USL), centered
/// difference (CD) and the update-velocity-first / modified USL variant (UVF-MPM, "musl").
enum class Integrator { usf, usl, cd, musl };

template <int Dim>
struct SimulationSpec {
  Vec<Dim> grid_lo = Vec<Dim>::Zero();  ///< position of the first node [m]
  Real h = 0;                           ///< cell width [m]
  IVec<Dim> cells{};                    ///< cells per axis
  Integrator integrator = Integrator::usl;
  KernelKind kernel = KernelKind::linear;
  /// Neo-Hookean (hyperelastic) and rate-form (hypoelastic, von Mises) materials, in any mix.
  std::vector<Material> materials;
  /// 2-D only: plane strain, or with rate-form materials plane stress and axisymmetry (masses and volumes of
  /// the particles given per unit thickness become per radian, times r).
  Geometry geometry = Geometry::plane_strain;
  BoundarySpec<Dim> boundary;
  std::vector<RigidBody<Dim>> rigid_bodies;
  /// Velocity fields and their contact (one field by default): each particle projects to field
  /// ParticleSet::field.
  ContactSpec contact;
  Vec<Dim> gravity = Vec<Dim>::Zero();  ///< [m/s^2]
  /// Local non-viscous damping alpha in [0, 1) of the grid update (node_update; Cundall 1987): 0 is none. It
  /// brings a body quasi-statically to equilibrium (a gravity ramp, a slope), and it is not
  /// energy-conserving.
  Real local_damping = 0;
  /// alpha of the FLIP-PIC blend of the particle velocity update, in [0, 1]:
  /// v_p = alpha (v_p + dt sum_i S_ip a_i) + (1 - alpha) sum_i S_ip v_i. 1 is FLIP (Wallstedt & Guilkey 2008,
  /// Eq. (18)), 0 is PIC, which filters each velocity mode by the kernel's P2G-G2P round trip every step (it
  /// dissipates; docs/transfers.md).
  Real flip_fraction = 1;
  /// APIC: v_p = sum_i S_ip v_i and B_p = sum_i S_ip v_i (x) (x_i - x_p) after the velocity update, P2G with
  /// m_p (v_p + B_p D_p^-1 (x_i - x_p)) (transfer/g2p.hpp, p2g.hpp; docs/transfers.md). flip_fraction
  /// stays 1.
  Transfer transfer = Transfer::flip;
  BodyForceFn<Dim> body_force;  ///< optional b(X, t), evaluated at the start of each step
  /// Pressures and tractions on the surfaces of bodies, carried by their surface particles as body forces.
  SurfaceLoads<Dim> surface_loads;
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

#pragma once
/// An explicit MPM/GIMP simulation: particles, grid, boundary conditions, and one time step per integrator.
#include <cstdint>
#include <limits>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_body.hpp"
#include "mpm/core/memory.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/grid/halo.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/particles/outflow.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/g2p_stress.hpp"
#include "mpm/transfer/p2g.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

template <int Dim, class Kernel>
class Simulation {
 public:
  /// Validate the spec and the particles (InputError on bad input) and set up the grid.
  Simulation(const SimulationSpec<Dim>& spec, ParticleSet<Dim> particles);

  /// Advance one time step of min(next_dt(), max_dt). Throws SimulationFailure (naming step, time, particle
  /// and cause) on a non-finite value, J <= 0, or a particle leaving the grid other than through an outflow face.
  /// Particles that crossed an outflow face stay in particles(), beyond the grid, until remove_outflow() or the
  /// next step, which begins with it.
  void step(Real max_dt = std::numeric_limits<Real>::infinity());
  /// Remove the particles beyond outflow faces, adding what they carry to outflow().
  void remove_outflow();
  /// What has left through the outflow faces since t = 0.
  const Outflow<Dim>& outflow() const { return outflow_; }
  /// Continue from a checkpoint taken after particles left: keep the first n particles (the restart overwrites
  /// their fields) and what had left.
  void restore_outflow(std::size_t n, const Outflow<Dim>& out);
  /// Stored energy of particle i: V0 W(F) of a Neo-Hookean particle (Wallstedt & Guilkey 2008, Eq. (54)), the
  /// internal energy of a rate-form one (Sulsky & Kaul 2004, Eq. (2.2.16)) [J].
  Real strain_energy(std::size_t i) const;
  /// Step until time t_end is reached (the last step is shortened to land on t_end).
  void run_until(Real t_end);

  Real time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  /// The time step the next call to step() will take (fixed, or from the CFL condition).
  Real next_dt() const;

  const ParticleSet<Dim>& particles() const { return particles_; }
  /// Mutable particles (restarts, scene set-up): the next step recomputes their stencils and their scatter order.
  ParticleSet<Dim>& particles() {
    stencils_current_ = false;
    tiles_changed_ = true;
    return particles_;
  }
  const Grid<Dim>& grid() const { return grid_; }
  /// Nodes at or below this mass are treated as empty (their acceleration is zero) [kg].
  Real min_node_mass() const { return min_node_mass_; }
  const KinematicConstraints<Dim>& constraints() const { return constraints_; }
  const RigidBodies<Dim>& rigid_bodies() const { return rigid_; }
  /// The Cauchy stress of particle i with its out-of-plane components [Pa] (a Neo-Hookean particle's from its
  /// in-plane stress and F).
  SymTensor<3> full_stress(std::size_t i) const;
  /// Body accelerations b(X_p, t^n) the last step used (empty without a body force).
  const std::vector<Vec<Dim>>& body_acceleration() const { return body_accel_; }
  /// Continue from a saved state: the particles are set already; this sets the clock (restarts).
  void restore_clock(Real time, std::int64_t steps) {
    time_ = time;
    steps_ = steps;
  }
  /// Continue from saved rigid-body displacements (restarts).
  void restore_rigid_bodies(const std::vector<Vec<Dim>>& displacement) { rigid_.restore(displacement); }
  const SimulationSpec<Dim>& spec() const { return spec_; }
  /// Heap bytes held by the simulation (particles, stencils, scatter order, grid) per particle.
  double bytes_per_particle() const;
  /// The bytes a simulation will hold, from the arrays the constructor sizes (a body force adds one
  /// acceleration per particle; a rate-form material its state and the rates the stress update reads).
  static MemoryModel memory_model(bool body_force, bool rate_form) {
    // Particles, their stencils, tiles and scatter order; one node record per node.
    const std::size_t particle =
        ParticleSet<Dim>::bytes_per_particle() + sizeof(Stencil<Dim, Kernel>) + 2 * sizeof(std::int32_t) +
        (body_force ? sizeof(Vec<Dim>) : 0) +
        (rate_form ? MaterialState::bytes_per_particle() + sizeof(Mat<Dim>) + sizeof(Real) : 0);
    // A node's mirror copies (1 B) when light nodes are re-projected.
    return {static_cast<double>(particle), static_cast<double>(sizeof(GridNode<Dim>) + sizeof(std::uint8_t))};
  }

 private:
  using StencilT = Stencil<Dim, Kernel>;

  // Time steps of each integrator (Wallstedt & Guilkey 2008, Sec. 2 and 4).
  void step_usf(Real dt);
  void step_usl(Real dt, Real accel_scale);
  void step_musl(Real dt, Real accel_scale);
  void reproject_velocity(Real t_new);
  /// Impose the faces' and the rigid bodies' velocities at t_new on the advanced grid velocity.
  void constrain_update(Real t_new, Real dt);

  // Stages shared by the integrators.
  void build_stencils();
  /// A P2G pass with its hoop force in axisymmetry, the halo sum and the symmetry folds.
  template <Scatter what>
  void scatter();
  /// A G2P pass after the halo copy; one that moves the particles also computes their stencils at the new positions.
  template <Gather what>
  void gather(NodeVelocity<Dim> v_grid, Real dt);
  void evaluate_body_force();
  /// The stress update of the rate-form (and, in a mixed table, Neo-Hookean) particles from the rates the last
  /// deforming G2P pass recorded.
  ParticleFault update_stress(Real dt);
  void check(ParticleFault fault, Real dt) const;
  /// Remove the particles at `gone` (ascending) with their per-particle arrays.
  void erase(const std::vector<std::size_t>& gone);

  SimulationSpec<Dim> spec_;
  ParticleSet<Dim> particles_;
  Grid<Dim> grid_;
  Halo<Dim> halo_;
  KinematicConstraints<Dim> constraints_;
  RigidBodies<Dim> rigid_;
  SizeUpdate sizes_;
  /// Every material Neo-Hookean: their laws, for the stress in G2P's lanes (empty otherwise).
  std::vector<NeoHookean> neo_hookean_;
  bool axisymmetric_;
  /// Rates the stress update reads when a material is rate-form: grad v [1/s] and v_r / r [1/s].
  std::vector<Mat<Dim>> grad_v_;
  std::vector<Real> hoop_rate_;
  Real min_node_mass_;
  /// Nodes with less mass get the re-projected velocity for positions and gradients (USL, CD); none when unset.
  LightMass<Dim> light_node_mass_;
  std::vector<std::uint8_t> mirror_copies_;  ///< per node, with light nodes: KinematicConstraints::count_mirror_copies
  std::vector<StencilT> stencils_;
  std::vector<std::int32_t> tile_;
  /// The stencils match the particles' positions (the last moving G2P pass computed them), and whether a
  /// particle changed tile since the scatter order was built.
  bool stencils_current_ = false, tiles_changed_ = false;
  ScatterOrder<Dim> order_;
  std::vector<Vec<Dim>> body_accel_;
  Outflow<Dim> outflow_;
  Real time_ = 0;
  std::int64_t steps_ = 0;
};

/// Call fn.template operator()<Kernel>() with the kernel policy for a kernel kind (coarse run-time choice).
template <class Fn>
decltype(auto) with_kernel(KernelKind k, Fn&& fn) {
  switch (k) {
    case KernelKind::linear:
      return fn.template operator()<LinearKernel>();
    case KernelKind::ugimp:
    case KernelKind::cpgimp:
      return fn.template operator()<GimpKernel>();
    case KernelKind::bspline2:
      return fn.template operator()<QuadraticBSplineKernel>();
    case KernelKind::bspline3:
      break;
  }
  return fn.template operator()<CubicBSplineKernel>();
}

}  // namespace mpm

#pragma once
/// Implicit MPM (Sulsky & Kaul 2004): a theta-blended step whose nodal velocities (or momenta) solve the
/// discrete momentum equation by matrix-free Newton-Krylov, with hypoelastic and von Mises materials, rigid
/// bodies, plane strain, plane stress and axisymmetry. theta = 0 gives the explicit method of the same
/// formulation, so explicit and implicit runs compare like with like.
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_bodies.hpp"
#include "mpm/core/memory.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/grid/periodic_halo.hpp"
#include "mpm/implicit/spec.hpp"
#include "mpm/particles/outflow.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

/// Work counters of a run, reported in summary.json.
struct ImplicitCounters {
  std::int64_t newton_iterations = 0;
  std::int64_t krylov_iterations = 0;
  std::int64_t residual_evaluations = 0;
  std::int64_t backtracks = 0;             ///< line-search step halvings
  std::int64_t retries = 0;                ///< time steps retried with half the step
  std::int64_t preconditioner_builds = 0;  ///< frozen-Jacobian assemblies and factorisations
};

/// One try at a time step: its step size and ||F|| at each Newton iterate, the initial guess first (empty for
/// theta = 0, the linear CG solve, and a try that failed before its Newton solve began).
struct NewtonAttempt {
  double dt = 0;
  std::vector<double> residual_norms;
};

template <int Dim, class Kernel>
class ImplicitSimulation {
 public:
  /// Validate the spec and the particles (InputError on bad input). In axisymmetric runs the particles'
  /// masses and volumes are areas times density and areas; they become per-radian values (times r).
  ImplicitSimulation(const ImplicitSpec<Dim>& spec, ParticleSet<Dim> particles);

  /// Advance one step of min(next_dt(), max_dt), halving and retrying when the solve fails. Throws
  /// SimulationFailure when the retries run out or a particle leaves the grid other than through an outflow
  /// face. Particles that crossed an outflow face stay in particles(), beyond the grid, until
  /// remove_outflow() or the next step, which begins with it.
  void step(Real max_dt = std::numeric_limits<Real>::infinity());
  /// Remove the particles beyond outflow faces, adding what they carry to outflow().
  void remove_outflow();
  /// What has left through the outflow faces since t = 0.
  const Outflow<Dim>& outflow() const { return outflow_; }
  /// Continue from a checkpoint: what had left through the outflow faces.
  void restore_outflow(const Outflow<Dim>& out) { outflow_ = out; }
  void run_until(Real t_end);
  /// The bytes a simulation will hold: particles with their material and trial states and stencils; per node
  /// the force fields, the unknowns' maps and the Krylov workspace (GMRES(restart): restart + 1 basis vectors
  /// and about seven work vectors of Dim values per node) and, with the frozen-Jacobian preconditioner, its
  /// sparse LU (Dim^2 (2 width - 1)^Dim entries of 12 B per node, times 4 for the fill-in of the factors: an
  /// estimate, measured within a factor 2 on the examples).
  static MemoryModel memory_model(int krylov_restart, bool frozen_jacobian) {
    constexpr double vec = sizeof(Vec<Dim>), real = sizeof(Real);
    const double state = MaterialState::bytes_per_particle();
    const double trial =
        sizeof(SymTensor<3>) + 4 * real + sizeof(InternalState) + sizeof(Mat<Dim>) + 2 * vec + 1;  // Trial
    const double particle = ParticleSet<Dim>::bytes_per_particle(reads_half_lengths<Kernel>) + state + trial +
                            sizeof(StoredStencil<Dim, Kernel>) + sizeof(std::int32_t);
    double node = sizeof(GridNode<Dim>) + 4 * vec + Dim * (sizeof(std::int32_t) + sizeof(std::int8_t)) +
                  (krylov_restart + 8) * Dim * real;
    if (frozen_jacobian) {
      double stencil_nodes = 1;
      for (int d = 0; d < Dim; ++d) stencil_nodes *= 2 * Kernel::width - 1;
      node += 4 * Dim * Dim * stencil_nodes * (real + sizeof(int));
    }
    return {particle, node};
  }

  Real time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  /// The explicit reference step (fixed at t = 0) and the step the next call will try.
  Real explicit_dt() const { return explicit_dt_; }
  Real next_dt() const { return dt_; }

  const ParticleSet<Dim>& particles() const { return particles_; }
  ParticleSet<Dim>& particles() { return particles_; }
  const MaterialState& state() const { return particles_.state; }
  MaterialState& state() { return particles_.state; }
  const KinematicConstraints<Dim>& constraints() const { return constraints_; }
  /// The grid: mass, velocity and acceleration of the last step's nodes (GridNode).
  const Grid<Dim>& grid() const { return grid_; }
  const ImplicitSpec<Dim>& spec() const { return spec_; }
  const ImplicitCounters& counters() const { return counters_; }
  /// Body accelerations b_p the last step used (empty without a body force) [m/s^2].
  const std::vector<Vec<Dim>>& body_acceleration() const { return body_accel_; }
  /// The surface loads of the last step (empty without surface loads).
  const SurfaceLoading<Dim>& surface_loading() const { return surface_; }
  /// Force [N per unit thickness or per radian] each grid-face constraint (in constraints().names() order)
  /// and each rigid body applied to the material over the last step.
  const std::vector<Vec<Dim>>& face_reactions() const { return face_reactions_; }
  const RigidBodies<Dim>& rigid_bodies() const { return rigid_; }
  const std::vector<Vec<Dim>>& rigid_reactions() const { return rigid_.reactions(); }
  /// Displacement of each rigid body since t = 0 [m].
  const std::vector<Vec<Dim>>& rigid_displacements() const { return rigid_.displacements(); }
  /// Newton iterations of the last step (0 for theta = 0).
  int last_newton_iterations() const { return last_newton_; }
  /// ||F|| at each Newton iterate of the last step's solve, the initial guess first (empty for theta = 0 and
  /// cg).
  const std::vector<double>& last_residual_norms() const { return attempts_.back().residual_norms; }
  /// The tries at the last step, halved ones first; after a SimulationFailure, those of the step that failed.
  const std::vector<NewtonAttempt>& last_step_attempts() const { return attempts_; }

  /// Continue from a saved state (particles and material state set already): the clock, step size and
  /// counters.
  void restore(Real time, std::int64_t steps, Real dt, const ImplicitCounters& counters,
               const std::vector<Vec<Dim>>& rigid_displacement);

 private:
  using StencilT = StoredStencil<Dim, Kernel>;
  /// The particles' stencils as the transfers read them.
  ParticleStencils<Dim, Kernel> stencils() const { return {stencils_, particles_}; }
  class Residual;
  struct Trial {  // particle state computed by one residual evaluation
    std::vector<SymTensor<3>> sigma;
    std::vector<Real> eps_bar, work, energy, stretch3;
    std::vector<InternalState> internal;
    std::vector<Mat<Dim>> grad_v;
    std::vector<Real> v_r;              // the radial velocity at the particle, sum_i N_i(x_p) v_ri^L
    std::vector<Vec<Dim>> v;            // v_p^L: Sulsky & Kaul 2004, Eq. (3.2.6) (momentum) or Eq. (2.3.3)
    std::vector<Vec<Dim>> x;            // x_p^L
    std::vector<Corners<Dim>> corners;  // CPDI2's x_c^L
    std::vector<std::uint8_t> ok;
  };

  bool try_step(Real dt);
  void project(Real dt);
  void build_dofs(Real t_new);
  /// sum_p N_i m_p v_p into GridNode::v_new, with APIC's affine part (AffineMomentum) when the run has one
  void scatter_momentum(const std::vector<Vec<Dim>>& v_p);
  /// The particles' APIC matrices for P2G, or none without APIC.
  const std::vector<Mat<Dim>>* affine() const {
    return spec_.transfer == Transfer::apic ? &particles_.B : nullptr;
  }
  void scatter_force(const std::vector<SymTensor<3>>& sigma, std::vector<Vec<Dim>>& f);
  void add_body_force(Real dt);
  /// G2P of a node vector field over the nodes that carry mass: out_p = sum_i N_i(x_p) value(node_i, i), with
  /// the value taken as zero at nodes of mass min_node_mass_ or less. Uses GridNode::a as scratch.
  template <class Value>
  void gather_over_active_nodes(Value value, std::vector<Vec<Dim>>& out);
  /// GridNode::a = value(node, n) on the nodes that carry mass, zero on the others.
  template <class Value>
  void put_on_active_nodes(Value value);
  void node_velocity_from(const Eigen::VectorXd& x);
  /// The consistent mass matrix (implicit.mass = "consistent"): u <- M u on the node field u, the projection
  /// of v^k with it, and the residual's inertia term M (v^L - v^k) into mass_dv_.
  void consistent_mass_times(std::vector<Vec<Dim>>& u);
  void project_consistent(Real dt);
  void consistent_inertia();
  bool residual_at(const Eigen::VectorXd& x, Real dt, Eigen::VectorXd& r);
  void accept(Real dt);
  void compute_reactions(Real dt);
  bool factorise_tangent(const Eigen::VectorXd& x, Real dt);
  /// The residual's scale 1 / (Y h^Dim dt) (Sulsky & Kaul 2004, Sec. 3.2.2).
  Real residual_scale(Real dt) const;

  /// The factorised tangent of preconditioner = "frozen-jacobian".
  struct TangentFactor;
  std::shared_ptr<TangentFactor> tangent_;

  ImplicitSpec<Dim> spec_;
  ParticleSet<Dim> particles_;
  Grid<Dim> grid_;
  PeriodicHalo<Dim> periodic_halo_;
  KinematicConstraints<Dim> constraints_;
  NodeLayout<Dim> layout_;
  Real min_node_mass_ = 0;
  Real modulus_ = 0;  // the largest Young's modulus: residual scale Y h^Dim dt (Sec. 3.2.2)
  std::vector<StencilT> stencils_;
  ScatterOrder<Dim> order_;
  RigidBodies<Dim> rigid_;
  // Nodes: internal force at t^k, external force, and the trial internal force of the last evaluation.
  std::vector<Vec<Dim>> f_k_, f_ext_, f_trial_;
  std::vector<Vec<Dim>> momentum_velocity_;  // momentum formulation: P_i^L / m_i
  std::vector<Vec<Dim>> dv_,
      v_move_;  // per particle: sum_i N_i (v_i^L - v_i^k), and the velocity that moves it
  std::vector<Vec<Dim>>
      pic_velocity_;  // flip_fraction < 1, moved by the re-projected velocity: sum_i N_i P_i^L / m_i
  std::vector<Mat<Dim>> affine_;  // APIC: the step's B_p, kept until the step is accepted
  std::vector<Vec<Dim>> mass_dv_,
      u_p_;  // consistent mass: M (v^L - v^k) per node; a node field at the particles
  // Unknowns: free (node, component) pairs; constrained ones with their value and owner (face group or rigid
  // body).
  std::vector<std::int32_t> dof_node_;
  std::vector<std::int8_t> dof_comp_;
  struct Fixed {
    std::int32_t node;
    int component;
    int owner;  // face group index, or groups + rigid body index
    Real value;
  };
  std::vector<Fixed> fixed_;
  /// The absorbing faces' dashpots, and their resistance on each free unknown (zero on most).
  std::vector<typename KinematicConstraints<Dim>::Dashpot> dashpots_;
  std::vector<Real> dof_resistance_;
  std::vector<std::uint8_t> mirrored_;  // nodes that copy another: symmetry ghosts, periodic images
  Trial trial_;
  Eigen::VectorXd last_x_;
  ImplicitCounters counters_;
  Outflow<Dim> outflow_;
  std::vector<Vec<Dim>> face_reactions_, body_accel_;
  SurfaceLoading<Dim> surface_;  ///< the surface loads, blended over the step as body_accel_
  Real explicit_dt_ = 0, dt_ = 0, time_ = 0;
  std::int64_t steps_ = 0;
  int last_newton_ = 0;
  std::vector<NewtonAttempt> attempts_ =
      std::vector<NewtonAttempt>(1);  // of the last step (one empty before any)
};

}  // namespace mpm

#pragma once
/// An explicit MPM/GIMP simulation: particles, grid, boundary conditions, and one time step per integrator.
#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_bodies.hpp"
#include "mpm/contact/multi_field.hpp"
#include "mpm/core/memory.hpp"
#include "mpm/distributed/box_halo.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/grid/periodic_halo.hpp"
#include "mpm/particles/outflow.hpp"
#include "mpm/particles/particle_sums.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/particles/reorder.hpp"
#include "mpm/shape/kernel_policies.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/passes.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

template <int Dim, class Kernel>
class Simulation {
 public:
  /// Validate the spec and the particles (InputError on bad input) and set up the grid. Among several ranks
  /// (`comm`), every rank passes all the particles: the grid is divided into one box per rank by bisection
  /// weighted by the particles (BoxHalo), and each rank keeps the particles of its box; periodic faces are
  /// refused there for now.
  Simulation(const SimulationSpec<Dim>& spec, ParticleSet<Dim> particles,
             const Communicator& comm = one_process());

  /// Advance one time step of min(next_dt(), max_dt). Throws SimulationFailure (naming step, time, particle
  /// and cause) on a non-finite value, J <= 0, or a particle leaving the grid other than through an outflow
  /// face. Particles that crossed an outflow face stay in particles(), beyond the grid, until
  /// remove_outflow() or the next step, which begins with it.
  void step(Real max_dt = std::numeric_limits<Real>::infinity());
  /// Remove the particles beyond outflow faces, adding what they carry to outflow().
  void remove_outflow();
  /// What has left through the outflow faces since t = 0.
  const Outflow<Dim>& outflow() const { return outflow_; }
  /// Continue from a checkpoint: what had left through the outflow faces.
  void restore_outflow(const Outflow<Dim>& out) { outflow_ = out; }
  /// Continue from particles set from a checkpoint, each rank holding any share of the whole set: the grid is
  /// divided again by them (as at the start), each goes to the rank that owns its tile, and they are settled.
  void adopt_particles();
  /// Stored energy of particle i: V0 W(F) of a Neo-Hookean particle (Wallstedt & Guilkey 2008, Eq. (54)), the
  /// internal energy of a rate-form one (Sulsky & Kaul 2004, Eq. (2.2.16)) [J].
  Real internal_energy(std::size_t i) const;
  /// Step until time t_end is reached (the last step is shortened to land on t_end).
  void run_until(Real t_end);

  Real time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  /// The time step the next call to step() will take (fixed, or from the CFL condition).
  Real next_dt() const;

  /// This rank's particles (all of them in one process).
  const ParticleSet<Dim>& particles() const { return particles_; }
  /// The ranks the run is divided between, and this rank's box of the grid.
  const Communicator& communicator() const { return *comm_; }
  const BoxHalo<Dim>& boxes() const { return box_halo_; }
  /// Times the grid was divided again since the start (rebalance()).
  int rebalances() const { return rebalances_; }
  /// Mutable particles (restarts, scene set-up): settle() or the next step recomputes their stencils and
  /// their scatter order.
  ParticleSet<Dim>& particles() {
    stencils_current_ = false;
    tiles_changed_ = true;
    return particles_;
  }
  /// Whether the particles carry a rate-form material state (ParticleSet::state): some material is rate-form.
  bool has_material_state() const { return neo_hookean_.empty(); }
  /// The particles' APIC matrices for P2G (AffineMomentum), or none without APIC.
  const std::vector<Mat<Dim>>* affine() const {
    return spec_.transfer == Transfer::apic ? &particles_.B : nullptr;
  }
  /// Locate the particles and store them in scatter order (by tile, then id), as every step leaves them.
  void settle();
  /// The power of gravity and the body force over the last step, sum_p m_p (g + b_p) . (v_p^n + v_p^{n+1}) /
  /// 2 over every rank's particles (each particle's load and velocities, however the particles moved between
  /// ranks after it) [W]; zero without loads or unless SimulationSpec::account_load_power.
  Real load_power() const { return load_power_; }
  /// Visit the particles in runs [begin, end) of one tile each (visit(begin, end)), whose exact sums
  /// (exact_run_sum) give the same bits whatever the division of the grid and the thread count: each tile's
  /// particles in id order. The particles must be settled (as every step, outflow removal and settle() leave
  /// them).
  template <class Visit>
  void for_each_sum_run(Visit&& visit) const {
    const StencilTiles<Dim, Kernel> tiles{stencils_};
    for_each_run(
        particles_.size(), [&](std::size_t i) { return tiles[i]; }, visit);
  }
  /// The grid of velocity field 0 (the only one without contact).
  const Grid<Dim>& grid() const { return grid_; }
  /// What each pair of SimulationSpec::contact's pairs transmitted in the last step, over all ranks (the
  /// force on the pair's first field by its second).
  std::vector<PairForces<Dim>> contact_forces() const;
  /// The nodes where velocity fields met in the last step, on this rank.
  std::size_t contact_nodes() const { return contact_.contact_nodes(); }
  /// Nodes at or below this mass are treated as empty (their acceleration is zero) [kg].
  Real min_node_mass() const { return min_node_mass_; }
  /// The id of the particle the last SimulationFailure named (the faulty one of least id on a divided grid),
  /// -1 before any.
  std::int64_t failed_particle() const { return failed_particle_; }
  const KinematicConstraints<Dim>& constraints() const { return constraints_; }
  /// The reaction of each face and region constraint (constraints().names()) in the last step, over all ranks
  /// [N].
  std::vector<Vec<Dim>> face_reactions() const;
  /// The power friction dissipated in the last step, over all ranks [W]: on the Coulomb walls and rigid
  /// bodies (friction_power of KinematicConstraints) and between the contact fields.
  Real friction_power() const;
  /// The spread of each face and region constraint's normal force in the last step, over all ranks [m]
  /// (contact_spread of the Coulomb walls; 0 for the other constraints).
  std::vector<Real> face_contact_spreads() const;
  /// The reaction of each rigid body in the last step, over all ranks [N].
  std::vector<Vec<Dim>> rigid_reactions() const;
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
  /// acceleration per particle, surface loads their SurfaceLoading; a rate-form material its state and the
  /// rates the stress update reads; USF with cpGIMP the half-lengths of the locate, `located_half_lengths`;
  /// `grids` node records per node: one per velocity field of contact, and one more each when contact
  /// measures gaps).
  static MemoryModel memory_model(bool body_force, bool rate_form, bool located_half_lengths, int grids = 1,
                                  bool surface_loads = false) {
    // Particles, their stencils and scatter order, the reorder's column; one node record per node.
    const std::size_t particle =
        ParticleSet<Dim>::bytes_per_particle(reads_half_lengths<Kernel>) +
        sizeof(StoredStencil<Dim, Kernel>) + sizeof(std::int32_t) +
        (located_half_lengths ? sizeof(Vec<Dim>) : 0) + (body_force ? sizeof(Vec<Dim>) : 0) +
        (surface_loads ? SurfaceLoading<Dim>::bytes_per_particle : 0) +
        (rate_form ? MaterialState::bytes_per_particle() + sizeof(Mat<Dim>) + sizeof(Real) : 0) +
        ReorderBuffer::column;
    // A node's mirror copies (1 B) when light nodes are re-projected.
    return {static_cast<double>(particle),
            static_cast<double>(grids * sizeof(GridNode<Dim>) + sizeof(std::uint8_t))};
  }

 private:
  using StencilT = StoredStencil<Dim, Kernel>;
  /// The particles' stencils as the transfers read them.
  ParticleStencils<Dim, Kernel> stencils() const {
    return {stencils_, particles_, located_half_lengths_.empty() ? nullptr : &located_half_lengths_};
  }
  // Time steps of each integrator (Wallstedt & Guilkey 2008, Sec. 2 and 4).
  void step_usf(Real dt);
  void step_usl(Real dt, Real accel_scale);
  void step_musl(Real dt, Real accel_scale);
  void reproject_velocity(Real t_new);
  /// Impose the faces' and the rigid bodies' velocities at t_new on the advanced grid velocity of every
  /// field.
  void constrain_update(Real t_new, Real dt);
  /// Impose them at time t on the node velocity `v` of every field (a projected velocity).
  void constrain_velocity(NodeVelocity<Dim> v, Real t);
  /// After the rigid bodies: the ghosts beyond symmetry planes reflect their real nodes' `values` again.
  void mirror_rigid_bodies(Grid<Dim>& field, std::initializer_list<NodeVelocity<Dim>> values);
  /// The grid velocity v^n from the scattered momenta, with contact's first correction, and the advanced
  /// velocity v_new from the forces with its second (Bardenhagen, Brackbill & Sulsky 2000), in every field.
  void grid_velocity_and_update(Real dt, Real accel_scale);
  /// v^n in every field, corrected by contact (its nodes located first when `locate`).
  void field_velocities(NodeVelocity<Dim> v, bool locate);
  /// The mass-weighted particle positions of each field at the nodes, for contact's gap (contact_positions_).
  void scatter_positions();
  /// Every field's grid: grid_ first, then the contact fields.
  std::vector<Grid<Dim>*> field_grids();

  // Stages shared by the integrators.
  /// What a step needs before its first pass: the stencils located and the particles settled into the scatter
  /// order (settle), the body force evaluated, the loads' start velocities and tiles kept, the rigid bodies
  /// located.
  void prepare_step();
  /// Keep the half-lengths the stencils were located with, where a pass changes them before the stencils'
  /// last use (USF with cpGIMP): located_half_lengths_, until the step ends.
  void keep_located_half_lengths();
  /// A P2G pass with its hoop force in axisymmetry, the halo sum and the symmetry folds.
  template <Scatter what>
  void scatter();
  /// The hoop force's pass in axisymmetry (HoopForce) of field `field`'s particles, after the main force pass
  /// and its halo sum.
  void scatter_hoop_force(Grid<Dim>& grid, int field) requires(Dim == 2);
  /// A G2P pass after the halo copy; one that moves the particles also computes their stencils at the new
  /// positions.
  template <Gather what>
  void gather(NodeVelocity<Dim> v_grid, Real dt);
  void evaluate_body_force();
  /// load_power_ of the step of length dt just taken, before the particles move between ranks.
  void account_load_power(Real dt);
  /// The stress update of the rate-form (and, in a mixed table, Neo-Hookean) particles from the rates the
  /// last deforming G2P pass recorded.
  ParticleFault update_stress(Real dt);
  /// Stop every rank with the failure of the first faulty particle (a SimulationFailure naming step, time,
  /// id, cause).
  void check(ParticleFault fault, Real dt);
  std::string failure_message(std::size_t i, Real dt) const;
  /// Remove the particles at `gone` (ascending) with their per-particle arrays.
  void erase(const std::vector<std::size_t>& gone);
  /// Size the rates the stress update reads to the particles (rate-form materials only).
  void size_rates();
  /// The particles whose tile another rank owns (ascending), and those ranks.
  std::vector<std::size_t> not_owned(std::vector<int>* owner = nullptr) const;
  /// Send the particles that moved into another rank's box there, and take in those that moved into this one.
  void migrate();
  /// Divide the grid again when the particles per rank have grown uneven (SimulationSpec::rebalance_above).
  void rebalance();
  /// The bisection of the grid weighted by every rank's particles, cut where the symmetry planes allow.
  BoxHalo<Dim> divide_by_particles() const;
  /// Take `box` as this rank's box: the grid and what is compiled for it (constraints, scatter order).
  void use_box(BoxHalo<Dim> box);

  SimulationSpec<Dim> spec_;
  ParticleSet<Dim> particles_;
  const Communicator* comm_;
  BoxHalo<Dim> box_halo_;
  Grid<Dim> grid_;
  /// Contact: the velocity fields past the first (grid_), one grid each, and the corrections where they meet.
  std::vector<Grid<Dim>> contact_fields_;
  MultiFieldContact<Dim> contact_;
  /// With gap detection, each field's sums m_p x_p S_ip (v slot) for its mass centres (scatter_positions).
  std::vector<Grid<Dim>> contact_positions_;
  PeriodicHalo<Dim> periodic_halo_;
  KinematicConstraints<Dim> constraints_;
  RigidBodies<Dim> rigid_;
  /// Every material Neo-Hookean: their laws, for the stress in G2P's lanes (empty otherwise).
  std::vector<NeoHookean> neo_hookean_;
  /// Every material Drucker-Prager: their rows, for the step in G2P's lanes (empty otherwise).
  std::vector<DruckerPragerRow> drucker_prager_;
  bool axisymmetric_;
  /// Rates the stress update reads when a material is rate-form, unless all are Drucker-Prager: grad v [1/s]
  /// and v_r / r [1/s].
  std::vector<Mat<Dim>> grad_v_;
  std::vector<Real> hoop_rate_;
  std::vector<Vec<Dim>> pic_velocity_;  ///< flip_fraction < 1: sum_i S_ip v_i of the velocity update
  Real min_node_mass_;
  /// Nodes with less mass get the re-projected velocity for positions and gradients (USL, CD); none when
  /// unset.
  LightMass<Dim> light_node_mass_;
  std::vector<Vec<Dim>> hoop_base_;  ///< divided axisymmetric runs: the node forces before the hoop pass
  std::vector<std::uint8_t>
      mirror_copies_;  ///< per node, with light nodes: KinematicConstraints::count_mirror_copies
  std::vector<StencilT> stencils_;
  /// The stencils match the particles' positions (the last moving G2P pass computed them), and whether a
  /// particle changed tile since the scatter order was built.
  bool stencils_current_ = false, tiles_changed_ = false;
  /// USF with cpGIMP, from its deformation pass to the step's end: the half-lengths of the stencils' locate
  /// (ParticleStencils); empty otherwise.
  std::vector<Vec<Dim>> located_half_lengths_;
  ScatterOrder<Dim> order_;
  ReorderBuffer reorder_buffer_;  ///< the reorder's scratch (settle)
  std::vector<Vec<Dim>> body_accel_;
  SurfaceLoading<Dim> surface_;  ///< the surface loads of the step (at its start)
  /// Loads, their velocities at the step's start (the particles' order then), their power over the last step.
  bool loads_;
  std::vector<Vec<Dim>> v_start_;
  std::vector<std::int32_t> start_tile_;
  Real load_power_ = 0;
  int rebalances_ = 0;
  std::int64_t last_rebalance_step_ = 0;
  Outflow<Dim> outflow_;
  Real time_ = 0;
  std::int64_t steps_ = 0;
  std::int64_t failed_particle_ = -1;  // failed_particle()
};

}  // namespace mpm

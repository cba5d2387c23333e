#pragma once
// Implementation of Simulation<Dim, Kernel>; included by the per-dimension instantiation files.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <variant>

#include "mpm/boundary/rigid_bodies_locate.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/time_step.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/pack.hpp"
#include "mpm/particles/reorder.hpp"
#include "mpm/particles/stable_step.hpp"
#include "mpm/particles/validate.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/g2p_stress.hpp"
#include "mpm/transfer/p2g.hpp"
#include "simulation_stress_impl.hpp"

namespace mpm {

/// Whether a kernel's gradient stays finite where its weight vanishes (see
/// LinearKernel::light_nodes_unbounded).
template <class Kernel>
constexpr bool light_nodes_unbounded() {
  if constexpr (requires { Kernel::light_nodes_unbounded; })
    return Kernel::light_nodes_unbounded;
  else
    return false;
}

namespace detail {
template <int Dim, class Kernel>
GridGeometry<Dim> make_geometry(const SimulationSpec<Dim>& spec) {
  validate(spec);
  GridGeometry<Dim> g{spec.grid_lo, spec.h, spec.cells, Kernel::ghost};
  g.periodic = periodic_axes(spec.boundary);
  g.outflow = outflow_faces(spec.boundary);
  g.walls = wall_faces(spec.boundary);
  g.clamped = clamped_faces(spec.kernel, spec.boundary);
  return g;
}

}  // namespace detail
}  // namespace mpm

#include "simulation_ranks_impl.hpp"
#include "simulation_stages_impl.hpp"

namespace mpm {

template <int Dim, class Kernel>
Simulation<Dim, Kernel>::Simulation(const SimulationSpec<Dim>& spec, ParticleSet<Dim> particles,
                                    const Communicator& comm)
    : spec_(spec),
      particles_(std::move(particles)),
      comm_(&comm),
      box_halo_(detail::divide<Dim, Kernel>(spec, particles_, comm)),
      grid_(box_halo_.box()),
      contact_fields_(static_cast<std::size_t>(spec.contact.fields - 1), grid_),
      contact_(spec.contact),
      contact_positions_(measures_gaps(spec.contact) ? static_cast<std::size_t>(spec.contact.fields) : 0,
                         grid_),
      periodic_halo_(grid_.geometry),
      constraints_(spec.boundary, grid_.geometry, box_halo_.owned_layers()),
      rigid_(spec.rigid_bodies, grid_.geometry, face_types(spec.boundary)),
      neo_hookean_(neo_hookean_only(spec.materials)),
      drucker_prager_(drucker_prager_rows(spec.materials)),
      axisymmetric_(Dim == 2 && spec.geometry == Geometry::axisymmetric),
      order_(grid_.geometry, Kernel::width),
      loads_(spec.account_load_power &&
             (spec.body_force || !spec.surface_loads.empty() || !spec.gravity.isZero(0))) {
  const GridGeometry<Dim>& g = grid_.geometry;
  ParticleSet<Dim>& p = particles_;
  p.half_lengths = half_lengths_of(spec.kernel);
  p.max_half_length = max_half_length(spec.kernel) * g.h;
  if (p.size() == 0) throw InputError("particles: the simulation has no particles");
  if (p.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw InputError("particles: more than 2^31 - 1 particles");
  const Real min_mass =
      start_particles(p, spec.materials, spec.kernel, g, axisymmetric_, spec.contact.fields);
  for (std::size_t i = 0; i < p.size(); ++i)  // the Neo-Hookean stress of F
    if (const auto* law = std::get_if<NeoHookean>(&spec.materials[p.material[i]]))
      p.sigma[i] = law->template stress<Dim>(p.F[i], p.F[i].determinant());
  // Nodes lighter than this are treated as empty (round-off level against the lightest particle).
  min_node_mass_ = 1e-14 * min_mass;
  // Light nodes, for kernels that need their treatment: less than a quarter of the lightest particle. The
  // strain a step adds through a node a particle reaches with weight S_ip is about CFL^2 (sigma / E) / S_ip
  // (Wallstedt & Guilkey 2008, Eq. (39)); the quarter bounds it by 4 CFL^2 sigma / E. No node of a body at
  // rest seeded at 2 or more particles per cell per axis is lighter (a face node gets 1/4 + 3/4 of a particle
  // per row); a particle that crosses into an empty cell makes one.
  if (light_nodes_unbounded<Kernel>() && spec.reproject_light_nodes) {
    light_node_mass_.mass = 0.25 * min_mass;
    if (axisymmetric_) {  // a quarter of the lightest particle per unit radius, at the node's radius
      Real min_per_radius = std::numeric_limits<Real>::max();
      for (std::size_t i = 0; i < p.size(); ++i)
        min_per_radius = std::min(min_per_radius, p.m[i] / p.X[i][0]);
      light_node_mass_.per_radius = 0.25 * min_per_radius;
      light_node_mass_.lo = g.lo[0];
      light_node_mass_.h = g.h;
      light_node_mass_.nodes_along = g.nodes_along(0);
      light_node_mass_.ghost = g.ghost;
    }
    mirror_copies_.assign(grid_.size(), 1);
    constraints_.count_mirror_copies(mirror_copies_);
  }
  if (spec.transfer == Transfer::apic)
    p.B.assign(p.size(), Mat<Dim>::Zero());                          // the particles start unsheared
  if constexpr (moves_corners<Kernel>) place_corners(p);             // CPDI2's domains start as CPDI's
  if constexpr (!reads_half_lengths<Kernel>) p.drop_half_lengths();  // read by no stage
  // Every rank was given all the particles (the masses above are the whole set's); each keeps its box's.
  if (box_halo_.divided()) erase_particles(p, not_owned());
  if (neo_hookean_.empty()) {
    // A state the particles bring (a geostatic stress) is kept; otherwise the rate-form solids start
    // unstressed.
    if (p.state.empty()) p.state.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) p.state.sigma[i] = full_stress(i);
    start_internal_state(spec.materials, p.material, p.state);
    size_rates();
  }
  prepare_step();  // sizes the per-particle arrays, so that steps do not allocate
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::size_rates() {
  if (!neo_hookean_.empty() || !drucker_prager_.empty()) return;
  grad_v_.resize(particles_.size(), Mat<Dim>::Zero());
  if (axisymmetric_) hoop_rate_.resize(particles_.size(), 0);
}

template <int Dim, class Kernel>
Real Simulation<Dim, Kernel>::next_dt() const {
  if (spec_.dt > 0) return spec_.dt;
  // Every rank takes the step of the fastest particle.
  return cfl_step(spec_.cfl, spec_.h, comm_->max(fastest_signal(particles_, spec_.materials)));
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step(Real max_dt) {
  remove_outflow();
  const Real stable_dt = next_dt();
  check_step_advances(steps_, time_, stable_dt);
  const Real dt = std::min(stable_dt, max_dt);
  // Centered difference starts from v^{-1/2} by halving the first grid acceleration, unless the particles
  // were given v^{-1/2} (Wallstedt & Guilkey 2008, Sec. 4); UVF-MPM is a modification of it and does the
  // same.
  const Real first_scale = steps_ == 0 && !spec_.half_step_velocity_given ? 0.5 : 1.0;
  switch (spec_.integrator) {
    case Integrator::usf:
      step_usf(dt);
      break;
    case Integrator::usl:
      step_usl(dt, 1.0);
      break;
    case Integrator::cd:
      step_usl(dt, first_scale);  // CD: USL, half-step start (Wallstedt & Guilkey 2008, Eq. (40) to Eq. (50))
      break;
    case Integrator::musl:
      step_musl(dt, first_scale);
      break;
  }
  if (loads_) account_load_power(dt);
  rigid_.advance(time_, dt);
  time_ += dt;
  ++steps_;
  if (box_halo_.divided()) {
    migrate();
    rebalance();
  }
  settle();  // between steps the particles are in scatter order, each on the rank that owns its tile
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::remove_outflow() {
  const std::vector<std::size_t> gone = beyond_outflow(particles_, grid_.geometry);
  bool faces = false;
  for (bool f : grid_.geometry.outflow) faces = faces || f;
  if (!faces) return;
  // What leaves now, over every rank, summed exactly: the same bits whatever the division. Terms: mass,
  // 1/2 m v^2, internal energy, m v.
  const ParticleSet<Dim>& p = particles_;
  std::vector<ExactSum> sums(3 + Dim);
  for (std::size_t i : gone) {
    sums[0].add(p.m[i]);
    sums[1].add(0.5 * p.m[i] * p.v[i].squaredNorm());
    sums[2].add(internal_energy(i));
    for (int d = 0; d < Dim; ++d) sums[3 + d].add(p.m[i] * p.v[i][d]);
  }
  std::vector<std::int64_t> count{static_cast<std::int64_t>(gone.size())};
  comm_->sum(count);
  if (count[0] == 0) return;
  const std::vector<Real> total = sum_over_ranks(sums, *comm_);
  outflow_.add_sums(count[0], total[0], Eigen::Map<const Vec<Dim>>(&total[3]), total[1], total[2]);
  erase(gone);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::erase(const std::vector<std::size_t>& gone) {
  const std::size_t n = particles_.size();
  erase_particles(particles_, gone);
  size_rates();
  // The rest keep their stencils and their order (by tile, then id); the scatter order's lists are rebuilt.
  if (stencils_.size() == n) {
    erase_at(stencils_, gone, n);
  } else {
    stencils_current_ = false;
  }
  tiles_changed_ = true;
}

template <int Dim, class Kernel>
Real Simulation<Dim, Kernel>::internal_energy(std::size_t i) const {
  const ParticleSet<Dim>& p = particles_;
  const Material& m = spec_.materials[p.material[i]];
  return is_rate_form(m)
             ? p.state.energy[i]
             : p.V0[i] * std::get<NeoHookean>(m).template energy_density<Dim>(p.F[i], p.F[i].determinant());
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::run_until(Real t_end) {
  while (time_ < t_end * (1 - 1e-14)) step(t_end - time_);
}

// USF: the stress is updated from the projected velocity before the forces are computed
// (Wallstedt & Guilkey 2008, Eq. (8) to Eq. (18)).
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step_usf(Real dt) {
  prepare_step();
  scatter<Scatter{.mass_momentum = true, .force = false, .volume_gradient = true}>();
  field_velocities(&GridNode<Dim>::v, true);
  for (Grid<Dim>* field : field_grids())
    for (GridNode<Dim>& node : field->nodes) node.v_new = node.v;
  constrain_velocity(&GridNode<Dim>::v_new, time_);
  keep_located_half_lengths();  // the deformation pass changes cpGIMP's, the force pass reads the stencils
                                // again
  gather<Gather{.velocity = false, .position = false, .deformation = true}>(&GridNode<Dim>::v_new, dt);
  scatter<Scatter{.mass_momentum = false, .force = true}>();
  for (Grid<Dim>* field : field_grids())
    grid_update(*field, spec_.gravity, dt, 1.0, min_node_mass_, spec_.local_damping);
  if (contact_.active()) contact_.correct_update(field_grids(), dt);
  constrain_update(time_ + dt, dt);
  gather<Gather{.velocity = true, .position = true, .deformation = false}>(&GridNode<Dim>::v_new, dt);
  located_half_lengths_.clear();  // the stencils just located are the particles' own
}

// USL: forces from the previous stress, then the stress is updated from the advanced grid velocity
// (Wallstedt & Guilkey 2008, Eq. (8), Eq. (9), Eq. (14) to Eq. (19)). With accel_scale = 1/2 on the first
// step this is the centered difference (Wallstedt & Guilkey 2008, Eq. (40) to Eq. (50)).
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step_usl(Real dt, Real accel_scale) {
  prepare_step();
  scatter<Scatter{.mass_momentum = true, .force = true, .volume_gradient = true}>();
  grid_velocity_and_update(dt, accel_scale);
  constrain_update(time_ + dt, dt);
  // Every rank takes the same path: a light node on any decides it.
  bool light = false;
  if (light_node_mass_.any())
    for (Grid<Dim>* field : field_grids())
      light = light || any_light(*field, mirror_copies_, min_node_mass_, light_node_mass_);
  if (!light_node_mass_.any() || !(comm_->max(light ? 1.0 : 0.0) > 0)) {
    gather<Gather{.velocity = true, .position = true, .deformation = true}>(&GridNode<Dim>::v_new, dt);
    return;
  }
  // Light nodes: move and deform the particles with the velocity re-projected from their updated velocities
  // there.
  gather<Gather{.velocity = true, .position = false, .deformation = false}>(&GridNode<Dim>::v_new, dt);
  reproject_velocity(time_ + dt);
  for (Grid<Dim>* field : field_grids())
    reprojected_on_light_nodes(*field, mirror_copies_, min_node_mass_, light_node_mass_);
  gather<Gather{.velocity = false, .position = true, .deformation = true}>(&GridNode<Dim>::v_new, dt);
}

// UVF-MPM / MUSL: as CD, but the grid velocity used for positions and gradients is re-projected from the
// updated particle velocities (Wallstedt & Guilkey 2008, Eq. (51) replaces Eq. (47)).
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step_musl(Real dt, Real accel_scale) {
  prepare_step();
  scatter<Scatter{.mass_momentum = true, .force = true, .volume_gradient = true}>();
  grid_velocity_and_update(dt, accel_scale);
  constrain_update(time_ + dt, dt);
  gather<Gather{.velocity = true, .position = false, .deformation = false}>(&GridNode<Dim>::v_new, dt);
  reproject_velocity(time_ + dt);
  gather<Gather{.velocity = false, .position = true, .deformation = true}>(&GridNode<Dim>::v, dt);
}

// The grid velocity v re-projected from the updated particle velocities, corrected by contact at the nodes
// the step located (the particles have not moved, so the nodal masses and normals are those of the step) and
// constrained at t_new (Wallstedt & Guilkey 2008, Eq. (51)).
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::reproject_velocity(Real t_new) {
  scatter<Scatter{.mass_momentum = true, .force = false}>();
  field_velocities(&GridNode<Dim>::v, false);
  constrain_velocity(&GridNode<Dim>::v, t_new);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::field_velocities(NodeVelocity<Dim> v, bool locate) {
  for (Grid<Dim>* field : field_grids()) grid_velocity(*field, min_node_mass_);
  if (!contact_.active()) return;
  if (locate) {
    if (!contact_positions_.empty()) scatter_positions();
    contact_.locate(field_grids(), min_node_mass_, box_halo_.owned_layers(), &contact_positions_);
  }
  contact_.correct_velocity(field_grids(), v);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::scatter_positions() {
  // Momentum<v slot, no mass> of the positions: sum_p m_p x_p S_ip, summed over boxes, periodic images and
  // mirrors as a momentum is (a mirror reflects it about the origin rather than the plane, which moves both
  // fields' mass centres alike and leaves their distance as it is).
  const Momentum<Dim, NodeSlots<Dim>::v, false> positions{particles_.m, particles_.x};
  for (int k = 0; k < contact_.fields(); ++k) {
    Grid<Dim>& grid = contact_positions_[static_cast<std::size_t>(k)];
    std::memset(static_cast<void*>(grid.nodes.data()), 0, grid.bytes());
    std::optional<FaceTileSums<Dim>> kept;
    if (box_halo_.divided()) kept.emplace(grid.geometry, order_);
    p2g_add_keeping(KeepFaceTiles<Dim>(kept), stencils(), order_, k, grid, positions);
    if (kept) box_halo_.sum(grid, kept->take(), true, false, *comm_);
    periodic_halo_.sum_into_owners(grid, &GridNode<Dim>::v);
    constraints_.fold_and_mirror(grid, &GridNode<Dim>::v);
  }
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::grid_velocity_and_update(Real dt, Real accel_scale) {
  if (!contact_.active()) {  // one pass over the nodes
    grid_velocity_update(grid_, spec_.gravity, dt, accel_scale, min_node_mass_, spec_.local_damping);
    return;
  }
  // Bardenhagen, Brackbill & Sulsky 2000: the projected velocities are corrected, then the advanced ones,
  // whose change over dt the accelerations take.
  field_velocities(&GridNode<Dim>::v, true);
  for (Grid<Dim>* field : field_grids())
    grid_update(*field, spec_.gravity, dt, accel_scale, min_node_mass_, spec_.local_damping);
  contact_.correct_update(field_grids(), dt);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::constrain_update(Real t_new, Real dt) {
  bool add = false;
  for (Grid<Dim>* field : field_grids()) {
    constraints_.constrain_update(*field, t_new, dt, add);
    rigid_.constrain_update(*field, t_new, dt, add);
    mirror_rigid_bodies(*field, {&GridNode<Dim>::a, &GridNode<Dim>::v_new});
    add = true;
  }
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::mirror_rigid_bodies(Grid<Dim>& field,
                                                  std::initializer_list<NodeVelocity<Dim>> values) {
  // A rigid body's update at a ghost beyond a symmetry plane is its own (a Coulomb body's normal there comes
  // from its points on one side only); the ghost must stay the reflection of its real node, which the
  // reactions count.
  if (rigid_.empty()) return;
  for (NodeVelocity<Dim> v : values) constraints_.mirror(field, v);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::constrain_velocity(NodeVelocity<Dim> v, Real t) {
  for (Grid<Dim>* field : field_grids()) {
    constraints_.constrain_velocity(*field, v, t);
    rigid_.constrain_velocity(*field, v, t);
    mirror_rigid_bodies(*field, {v});
  }
}

template <int Dim, class Kernel>
std::vector<Grid<Dim>*> Simulation<Dim, Kernel>::field_grids() {
  std::vector<Grid<Dim>*> out{&grid_};
  for (Grid<Dim>& g : contact_fields_) out.push_back(&g);
  return out;
}

}  // namespace mpm

#pragma once
// Implementation of Simulation<Dim, Kernel>; included by the per-dimension instantiation files.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <variant>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/pack.hpp"
#include "mpm/particles/reorder.hpp"
#include "mpm/transfer/p2g.hpp"
#include "simulation_stress_impl.hpp"

namespace mpm {

/// Whether a kernel's gradient stays finite where its weight vanishes (see LinearKernel::light_nodes_unbounded).
template <class Kernel>
constexpr bool light_nodes_unbounded() {
  if constexpr (requires { Kernel::light_nodes_unbounded; })
    return Kernel::light_nodes_unbounded;
  else
    return false;
}

namespace detail {
template <int Dim>
std::string format(const Vec<Dim>& x) {
  std::ostringstream os;
  os.precision(9);
  os << '(';
  for (int d = 0; d < Dim; ++d) os << (d ? ", " : "") << x[d];
  os << ')';
  return os.str();
}

template <int Dim, class Kernel>
GridGeometry<Dim> make_geometry(const SimulationSpec<Dim>& spec) {
  validate(spec);
  GridGeometry<Dim> g{spec.grid_lo, spec.h, spec.cells, Kernel::ghost};
  g.periodic = periodic_axes(spec.boundary);
  g.outflow = outflow_faces(spec.boundary);
  return g;
}

/// The global storage layer of the base node of the stencil of a particle at x with half-lengths l: the layers
/// make_stencil computes, before a box's offset is subtracted.
template <int Dim, class Kernel>
IVec<Dim> base_layer(const GridGeometry<Dim>& whole, const Vec<Dim>& x, const Vec<Dim>& l) {
  const Real inv_h = 1 / whole.h;
  IVec<Dim> s;
  typename Kernel::Axis axis;
  for (int d = 0; d < Dim; ++d) s[d] = Kernel::locate((x[d] - whole.lo[d]) * inv_h, l[d] * inv_h, axis) + whole.ghost;
  return s;
}

/// The division of the grid between the ranks of comm: bisection of the tiles weighted by the particles in
/// them, cut where the symmetry planes allow (cut_limit).
template <int Dim, class Kernel>
BoxHalo<Dim> divide(const SimulationSpec<Dim>& spec, const ParticleSet<Dim>& p, const Communicator& comm) {
  const GridGeometry<Dim> whole = make_geometry<Dim, Kernel>(spec);
  if (comm.size() == 1) return BoxHalo<Dim>(whole);
  const auto refuse = [&](const std::string& what) {
    throw InputError(what + " run in one process for now (docs/scaling.md); start mpm without mpirun or srun");
  };
  for (const FaceCondition<Dim>& f : spec.boundary.faces) {
    if (f.type == FaceType::periodic) refuse("periodic faces");
    if (f.type == FaceType::outflow) refuse("outflow faces");
  }
  if (Dim == 2 && spec.geometry == Geometry::axisymmetric) refuse("axisymmetric runs");
  if (!spec.rigid_bodies.empty()) refuse("rigid bodies");
  IVec<Dim> tiles;
  for (int d = 0; d < Dim; ++d) tiles[d] = whole.tiles_along(d);
  std::vector<std::int64_t> weight(whole.tile_count(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!whole.contains(p.x[i])) continue;  // refused by the constructor, with its index
    const IVec<Dim> s = base_layer<Dim, Kernel>(whole, p.x[i], p.l[i]);
    std::int64_t flat = 0;
    bool inside = true;
    for (int d = Dim - 1; d >= 0; --d) {
      const int t = s[d] >> GridGeometry<Dim>::tile_shift;
      inside = inside && t >= 0 && t < tiles[d];
      flat = flat * tiles[d] + t;
    }
    if (inside) ++weight[static_cast<std::size_t>(flat)];
  }
  std::array<bool, Dim> symmetric_high;
  for (int d = 0; d < Dim; ++d) symmetric_high[d] = spec.boundary.faces[2 * d + 1].type == FaceType::symmetry;
  return BoxHalo<Dim>(whole, bisect<Dim>(tiles, weight, comm.size(), cut_limit<Dim>(whole, symmetric_high, Kernel::width)),
                      comm.rank(), Kernel::width);
}
}  // namespace detail

template <int Dim, class Kernel>
Simulation<Dim, Kernel>::Simulation(const SimulationSpec<Dim>& spec, ParticleSet<Dim> particles,
                                    const Communicator& comm)
    : spec_(spec),
      particles_(std::move(particles)),
      comm_(&comm),
      box_halo_(detail::divide<Dim, Kernel>(spec, particles_, comm)),
      grid_(box_halo_.box()),
      halo_(grid_.geometry),
      constraints_(spec.boundary, grid_.geometry, box_halo_.owned_layers()),
      rigid_(spec.rigid_bodies, grid_.geometry),
      sizes_(spec.kernel == KernelKind::cpgimp ? SizeUpdate::deformed : SizeUpdate::fixed),
      neo_hookean_(neo_hookean_only(spec.materials)),
      axisymmetric_(Dim == 2 && spec.geometry == Geometry::axisymmetric),
      order_(grid_.geometry, Kernel::width),
      loads_(spec.body_force || !spec.gravity.isZero(0)) {
  const GridGeometry<Dim>& g = grid_.geometry;
  ParticleSet<Dim>& p = particles_;
  if (p.size() == 0) throw InputError("particles: the simulation has no particles");
  if (p.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw InputError("particles: more than 2^31 - 1 particles");
  Real min_mass = std::numeric_limits<Real>::max();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::string at = "particle " + std::to_string(i);
    if (!g.contains(p.x[i]))
      throw InputError(at + " at " + detail::format<Dim>(p.x[i]) + " lies outside the grid " +
                       detail::format<Dim>(g.lo) + " - " + detail::format<Dim>(g.hi()));
    if (!(p.m[i] > 0) || !(p.V0[i] > 0)) throw InputError(at + ": mass and volume must be positive");
    if (p.material[i] >= spec.materials.size())
      throw InputError(at + ": material index " + std::to_string(p.material[i]) + " has no material");
    if (!p.v[i].allFinite()) throw InputError(at + ": velocity must be finite");
    const Material& material = spec.materials[p.material[i]];
    if (is_rate_form(material) && !(p.F[i] - Mat<Dim>::Identity()).isZero(0))
      throw InputError(at + ": the rate-form materials start undeformed (F = I)");
    if (axisymmetric_) {
      if (!(p.X[i][0] > 0)) throw InputError(at + ": axisymmetric particles need radius x > 0");
      p.m[i] *= p.X[i][0];  // per radian: m_p = rho r_p A_p
      p.V0[i] *= p.X[i][0];
    }
    if (spec.kernel == KernelKind::ugimp || spec.kernel == KernelKind::cpgimp)
      for (int d = 0; d < Dim; ++d)
        if (!(p.l[i][d] > 0 && p.l[i][d] <= 0.5 * g.h))
          throw InputError(at + ": GIMP half-length " + std::to_string(p.l[i][d]) + " must lie in (0, h/2]");
    const Real J = p.F[i].determinant();
    p.V[i] = p.V0[i] * J;
    if (!(J > 0)) throw InputError(at + ": deformation gradient must have det F > 0");
    if (!is_rate_form(material)) p.sigma[i] = std::get<NeoHookean>(material).template stress<Dim>(p.F[i], J);
    min_mass = std::min(min_mass, p.m[i]);
  }
  // Nodes lighter than this are treated as empty (round-off level against the lightest particle).
  min_node_mass_ = 1e-14 * min_mass;
  // Light nodes, for kernels that need their treatment: less than a quarter of the lightest particle. The strain
  // a step adds through a node a particle reaches with weight S_ip is about CFL^2 (sigma / E) / S_ip (Wallstedt &
  // Guilkey 2008, Eq. (39)); the quarter bounds it by 4 CFL^2 sigma / E. No node of a body at rest seeded at 2 or
  // more particles per cell per axis is lighter (a face node gets 1/4 + 3/4 of a particle per row); a particle
  // that crosses into an empty cell makes one.
  if (light_nodes_unbounded<Kernel>() && spec.reproject_light_nodes) {
    light_node_mass_.mass = 0.25 * min_mass;
    if (axisymmetric_) {  // a quarter of the lightest particle per unit radius, at the node's radius
      Real min_per_radius = std::numeric_limits<Real>::max();
      for (std::size_t i = 0; i < p.size(); ++i) min_per_radius = std::min(min_per_radius, p.m[i] / p.X[i][0]);
      light_node_mass_.per_radius = 0.25 * min_per_radius;
      light_node_mass_.lo = g.lo[0];
      light_node_mass_.h = g.h;
      light_node_mass_.nodes_along = g.nodes_along(0);
      light_node_mass_.ghost = g.ghost;
    }
    mirror_copies_.assign(grid_.size(), 1);
    constraints_.count_mirror_copies(mirror_copies_);
  }
  // Every rank was given all the particles (the masses above are the whole set's); each keeps its box's.
  if (box_halo_.divided()) erase_particles(p, not_owned());
  if (neo_hookean_.empty()) {
    p.state.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) p.state.sigma[i] = full_stress(i);
    size_rates();
  }
  build_stencils();  // sizes the per-particle arrays, so that steps do not allocate
}

template <int Dim, class Kernel>
std::vector<Vec<Dim>> Simulation<Dim, Kernel>::face_reactions() const {
  if (!box_halo_.divided()) return constraints_.reactions();
  std::vector<std::int64_t> integers;
  for (const std::array<ExactSum, Dim>& r : constraints_.reaction_sums())
    for (const ExactSum& e : r) {
      const std::vector<std::int64_t> mine = e.integers();
      integers.insert(integers.end(), mine.begin(), mine.end());
    }
  comm_->sum(integers);
  std::vector<Vec<Dim>> out(constraints_.reaction_sums().size());
  auto at = integers.begin();
  for (Vec<Dim>& r : out)
    for (int d = 0; d < Dim; ++d, at += ExactSum::integer_count)
      r[d] = ExactSum::from_integers({at, at + ExactSum::integer_count}).value();
  return out;
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::size_rates() {
  if (!neo_hookean_.empty()) return;
  grad_v_.resize(particles_.size(), Mat<Dim>::Zero());
  if (axisymmetric_) hoop_rate_.resize(particles_.size(), 0);
}

template <int Dim, class Kernel>
std::vector<std::size_t> Simulation<Dim, Kernel>::not_owned(std::vector<int>* owner) const {
  std::vector<std::size_t> out;
  const ParticleSet<Dim>& p = particles_;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int r = box_halo_.owner(detail::base_layer<Dim, Kernel>(box_halo_.whole(), p.x[i], p.l[i]));
    if (r == comm_->rank()) continue;
    out.push_back(i);
    if (owner) owner->push_back(r);
  }
  return out;
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::migrate() {
  std::vector<int> owner;
  const std::vector<std::size_t> leaving = not_owned(&owner);
  std::vector<std::vector<std::byte>> to(static_cast<std::size_t>(comm_->size()));
  const bool with_state = neo_hookean_.empty();
  for (std::size_t k = 0; k < leaving.size(); ++k)
    pack_particle(particles_, leaving[k], with_state, to[static_cast<std::size_t>(owner[k])]);
  if (!leaving.empty()) erase(leaving);
  const std::vector<std::vector<std::byte>> from = comm_->exchange(to);
  bool arrived = false;
  for (const std::vector<std::byte>& bytes : from) {
    arrived = arrived || !bytes.empty();
    unpack_particles(bytes, with_state, particles_);
  }
  if (!arrived) return;
  size_rates();
  stencils_current_ = false;  // the next step locates them and sorts them into the scatter order
}

template <int Dim, class Kernel>
Real Simulation<Dim, Kernel>::next_dt() const {
  if (spec_.dt > 0) return spec_.dt;
  const ParticleSet<Dim>& p = particles_;
  Real speed = 0;
  if (!neo_hookean_.empty()) {
#pragma omp parallel for reduction(max : speed)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(p.size()); ++i)
      speed = std::max(speed, neo_hookean_[p.material[i]].wave_speed(p.V[i] / p.V0[i]) + p.v[i].norm());
  } else {
#pragma omp parallel for reduction(max : speed)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(p.size()); ++i)
      speed = std::max(speed, wave_speed(spec_.materials[p.material[i]], p.V[i] / p.V0[i]) + p.v[i].norm());
  }
  return spec_.cfl * spec_.h / comm_->max(speed);  // every rank takes the step of the fastest particle
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step(Real max_dt) {
  remove_outflow();
  const Real dt = std::min(next_dt(), max_dt);
  // Centered difference starts from v^{-1/2} by halving the first grid acceleration, unless the particles were
  // given v^{-1/2} (Wallstedt & Guilkey 2008, Sec. 4); UVF-MPM is a modification of it and does the same.
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
  if (loads_) account_load_power();
  rigid_.advance(time_, dt);
  time_ += dt;
  ++steps_;
  if (box_halo_.divided()) migrate();
  settle();  // between steps the particles are in scatter order, each on the rank that owns its tile
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::remove_outflow() {
  const std::vector<std::size_t> gone = beyond_outflow(particles_, grid_.geometry);
  if (gone.empty()) return;
  for (std::size_t i : gone) outflow_.add(particles_, i, strain_energy(i));
  erase(gone);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::restore_outflow(std::size_t n, const Outflow<Dim>& out) {
  erase(indices_from(n, particles_.size()));
  outflow_ = out;
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::erase(const std::vector<std::size_t>& gone) {
  const std::size_t n = particles_.size();
  erase_particles(particles_, gone);
  size_rates();
  // The rest keep their stencils and their order (by tile, then id); the scatter order's lists are rebuilt.
  if (stencils_.size() == n) {
    erase_at(stencils_, gone, n);
    erase_at(tile_, gone, n);
  } else {
    stencils_current_ = false;
  }
  tiles_changed_ = true;
}

template <int Dim, class Kernel>
Real Simulation<Dim, Kernel>::strain_energy(std::size_t i) const {
  const ParticleSet<Dim>& p = particles_;
  const Material& m = spec_.materials[p.material[i]];
  return is_rate_form(m) ? p.state.energy[i]
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
  build_stencils();
  scatter<Scatter{.mass_momentum = true, .force = false}>();
  grid_velocity(grid_, min_node_mass_);
  for (GridNode<Dim>& node : grid_.nodes) node.v_new = node.v;
  constraints_.constrain_velocity(grid_, &GridNode<Dim>::v_new, time_);
  rigid_.constrain_velocity(grid_, &GridNode<Dim>::v_new, time_);
  gather<Gather{.velocity = false, .position = false, .deformation = true}>(&GridNode<Dim>::v_new, dt);
  scatter<Scatter{.mass_momentum = false, .force = true}>();
  grid_update(grid_, spec_.gravity, dt, 1.0, min_node_mass_);
  constrain_update(time_ + dt, dt);
  gather<Gather{.velocity = true, .position = true, .deformation = false}>(&GridNode<Dim>::v_new, dt);
}

// USL: forces from the previous stress, then the stress is updated from the advanced grid velocity
// (Wallstedt & Guilkey 2008, Eq. (8), Eq. (9), Eq. (14) to Eq. (19)). With accel_scale = 1/2 on the first step
// this is the centered difference (Wallstedt & Guilkey 2008, Eq. (40) to Eq. (50)).
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step_usl(Real dt, Real accel_scale) {
  build_stencils();
  scatter<Scatter{.mass_momentum = true, .force = true}>();
  grid_velocity_update(grid_, spec_.gravity, dt, accel_scale, min_node_mass_);
  constrain_update(time_ + dt, dt);
  // Every rank takes the same path: a light node on any decides it.
  if (!light_node_mass_.any() ||
      !(comm_->max(any_light(grid_, mirror_copies_, min_node_mass_, light_node_mass_) ? 1.0 : 0.0) > 0)) {
    gather<Gather{.velocity = true, .position = true, .deformation = true}>(&GridNode<Dim>::v_new, dt);
    return;
  }
  // Light nodes: move and deform the particles with the velocity re-projected from their updated velocities there.
  gather<Gather{.velocity = true, .position = false, .deformation = false}>(&GridNode<Dim>::v_new, dt);
  reproject_velocity(time_ + dt);
  reprojected_on_light_nodes(grid_, mirror_copies_, min_node_mass_, light_node_mass_);
  gather<Gather{.velocity = false, .position = true, .deformation = true}>(&GridNode<Dim>::v_new, dt);
}

// UVF-MPM / MUSL: as CD, but the grid velocity used for positions and gradients is re-projected from the
// updated particle velocities (Wallstedt & Guilkey 2008, Eq. (51) replaces Eq. (47)).
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::step_musl(Real dt, Real accel_scale) {
  build_stencils();
  scatter<Scatter{.mass_momentum = true, .force = true}>();
  grid_velocity_update(grid_, spec_.gravity, dt, accel_scale, min_node_mass_);
  constrain_update(time_ + dt, dt);
  gather<Gather{.velocity = true, .position = false, .deformation = false}>(&GridNode<Dim>::v_new, dt);
  reproject_velocity(time_ + dt);
  gather<Gather{.velocity = false, .position = true, .deformation = true}>(&GridNode<Dim>::v, dt);
}

// The grid velocity v re-projected from the updated particle velocities, constrained at t_new (Wallstedt &
// Guilkey 2008, Eq. (51)); the particles have not moved, so the nodal masses are those of the step.
template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::reproject_velocity(Real t_new) {
  scatter<Scatter{.mass_momentum = true, .force = false}>();
  grid_velocity(grid_, min_node_mass_);
  constraints_.constrain_velocity(grid_, &GridNode<Dim>::v, t_new);
  rigid_.constrain_velocity(grid_, &GridNode<Dim>::v, t_new);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::constrain_update(Real t_new, Real dt) {
  constraints_.constrain_update(grid_, t_new, dt);
  rigid_.constrain_update(grid_, t_new, dt);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::settle() {
  if (!stencils_current_)
    tiles_changed_ = mpm::build_stencils<Dim, Kernel>(particles_, grid_.geometry, stencils_, tile_) || tiles_changed_;
  // The scatter order depends only on the tiles, so it is rebuilt only when a particle changed tile; the
  // particles are then stored in that order, so that the transfers read them in sequence.
  if (tiles_changed_) {
    order_.build(tile_, particles_.id);
    if (!order_.identity()) {
      reorder_particles(particles_, order_.order());
      gather_by(stencils_, order_.order());
      gather_by(tile_, order_.order());
      order_.reordered();
    }
  }
  stencils_current_ = true;
  tiles_changed_ = false;
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::build_stencils() {
  settle();
  evaluate_body_force();
  if (loads_) {
    v_start_ = particles_.v;
    start_tile_ = tile_;
  }
  if (!rigid_.empty()) {
    std::ostringstream when;
    when.precision(9);
    when << "step " << steps_ + 1 << ", t = " << time_;
    rigid_.template locate<Kernel>(grid_.geometry, when.str());
  }
}

template <int Dim, class Kernel>
template <Scatter what>
void Simulation<Dim, Kernel>::scatter() {
  if (box_halo_.divided()) {  // the halo sum: the sums of tiles of other boxes at the nodes they share
    const FaceTileSums<Dim> kept(grid_.geometry, order_);
    p2g<what>(particles_, stencils_, order_, body_accel_, grid_, kept);
    box_halo_.sum(grid_, kept.take(), what.mass_momentum, what.force, *comm_);
  } else {
    p2g<what>(particles_, stencils_, order_, body_accel_, grid_);
  }
  if constexpr (what.force && Dim == 2)  // the hoop force in a pass of its own, as in the implicit step
    if (axisymmetric_) p2g_add(stencils_, order_, grid_, HoopForce{particles_.V, particles_.state.sigma, particles_.x});
  if constexpr (what.mass_momentum) halo_.sum_into_owners(grid_, NodeFields::mass_momentum);
  if constexpr (what.force) halo_.sum_into_owners(grid_, NodeFields::force);
  if constexpr (what.mass_momentum) constraints_.fold_and_mirror(grid_, NodeFields::mass_momentum);
  if constexpr (what.force) constraints_.fold_and_mirror(grid_, NodeFields::force);
}

template <int Dim, class Kernel>
template <Gather what>
void Simulation<Dim, Kernel>::gather(NodeVelocity<Dim> v_grid, Real dt) {
  halo_.copy_to_ghosts(grid_);
  StencilTargets<Dim, Kernel> next{stencils_, tile_};
  StencilTargets<Dim, Kernel>* targets = what.position ? &next : nullptr;
  ParticleFault fault;
  if (!neo_hookean_.empty()) {
    fault = g2p<what>(particles_, stencils_, grid_, v_grid, dt, NeoHookeanLanes{neo_hookean_}, sizes_, targets);
  } else {
    const RecordRates<Dim> rates{grad_v_, hoop_rate_, axisymmetric_};
    fault = g2p<what>(particles_, stencils_, grid_, v_grid, dt, rates, sizes_, targets);
    if constexpr (what.deformation) {
      const ParticleFault stress = update_stress(dt);
      fault.index = std::min(fault.index, stress.index);
    }
  }
  check(fault, dt);
  if constexpr (what.position) {
    stencils_current_ = true;
    tiles_changed_ = tiles_changed_ || next.tile_changed.load();
  }
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::account_load_power() {
  // Grouped by the tiles of the step's start, whose particles one rank held, in id order.
  const ParticleSet<Dim>& p = particles_;
  load_power_ = sum_by_tile<1>([&](std::size_t i) { return start_tile_[i]; }, [&](std::size_t i) {
    const Vec<Dim> load = body_accel_.empty() ? spec_.gravity : Vec<Dim>(spec_.gravity + body_accel_[i]);
    return std::array<Real, 1>{p.m[i] * load.dot(0.5 * (v_start_[i] + p.v[i]))};
  })[0];
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::evaluate_body_force() {
  if (!spec_.body_force) return;
  body_accel_.resize(particles_.size());
  parallel_for(static_cast<std::ptrdiff_t>(particles_.size()),
               [&](std::ptrdiff_t i) { body_accel_[i] = spec_.body_force(particles_.X[i], time_); });
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::check(ParticleFault fault, Real dt) const {
  const ParticleSet<Dim>& p = particles_;
  if (!box_halo_.divided()) {
    if (fault) throw SimulationFailure(failure_message(static_cast<std::size_t>(fault.index), dt));
    return;
  }
  // Every rank learns of the failure: the one holding the faulty particle of least id says why.
  constexpr std::int64_t none = std::numeric_limits<std::int64_t>::max();
  const std::int64_t mine = fault ? p.id[static_cast<std::size_t>(fault.index)] : none;
  const std::int64_t first = comm_->min(mine);
  if (first == none) return;
  const int root = static_cast<int>(comm_->min(mine == first ? comm_->rank() : comm_->size()));
  std::vector<std::byte> message;
  if (mine == first) {
    const std::string text = failure_message(static_cast<std::size_t>(fault.index), dt);
    for (char c : text) message.push_back(static_cast<std::byte>(c));
  }
  message = comm_->broadcast(std::move(message), root);
  std::string text;
  for (std::byte b : message) text.push_back(static_cast<char>(b));
  throw SimulationFailure(text);
}

template <int Dim, class Kernel>
std::string Simulation<Dim, Kernel>::failure_message(std::size_t i, Real dt) const {
  const ParticleSet<Dim>& p = particles_;
  const Real J = p.F[i].determinant();
  std::string cause;
  if (!p.x[i].allFinite() || !p.v[i].allFinite() || !std::isfinite(J))
    cause = "non-finite position, velocity or deformation gradient";
  else if (!grid_.geometry.contains(p.x[i]))
    cause = "left the grid at " + detail::format<Dim>(p.x[i]);
  else if (!(J > 0))
    cause = "det F = " + std::to_string(J) + " <= 0 (material inverted)";
  else if (!p.state.empty() && !(p.state.stretch3[i] > 0 && p.V[i] > 0))
    cause = "volume V / V0 = " + std::to_string(p.V[i] / p.V0[i]) + " with out-of-plane stretch " +
            std::to_string(p.state.stretch3[i]) + " (material inverted)";
  else if (!p.state.empty() && !p.state.sigma[i].full().allFinite())
    cause = "non-finite stress from the material update";
  else
    cause = "cpGIMP half-lengths " + detail::format<Dim>(p.l[i]) + " left (0, h/2] (deformation too large)";
  std::ostringstream os;
  os.precision(9);
  os << "step " << steps_ + 1 << ", t = " << time_ + dt << ": particle " << p.id[i] << ": " << cause;
  return os.str();
}

template <int Dim, class Kernel>
double Simulation<Dim, Kernel>::bytes_per_particle() const {
  const double n = static_cast<double>(particles_.size());
  return static_cast<double>(particles_.bytes_per_particle()) + sizeof(StencilT) +
         static_cast<double>(order_.bytes() + tile_.capacity() * sizeof(std::int32_t) +
                             body_accel_.capacity() * sizeof(Vec<Dim>) + grid_.bytes() +
                             (particles_.state.empty() ? 0 : particles_.size() * MaterialState::bytes_per_particle()) +
                             grad_v_.capacity() * sizeof(Mat<Dim>) + hoop_rate_.capacity() * sizeof(Real)) /
             n;
}

}  // namespace mpm

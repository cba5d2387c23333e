#pragma once
// The parts of Simulation<Dim, Kernel> that divide a run between ranks (mpm/distributed): the division of the
// grid, the particles a rank owns and their migration, the failures and reactions agreed over all ranks.
// Included by simulation_impl.hpp.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/pack.hpp"

namespace mpm {
namespace detail {

/// The global storage layer of the base node of the stencil of a particle at x with half-lengths l: the
/// layers make_stencil computes, before a box's offset is subtracted.
template <int Dim, class Kernel>
IVec<Dim> base_layer(const GridGeometry<Dim>& whole, const Vec<Dim>& x, const Vec<Dim>& l) {
  const Real inv_h = 1 / whole.h;
  IVec<Dim> s;
  typename BoxKernel<Kernel>::Axis axis;
  for (int d = 0; d < Dim; ++d)
    s[d] = locate_axis<BoxKernel<Kernel>>(whole, d, (x[d] - whole.lo[d]) * inv_h, l[d] * inv_h, axis) +
           whole.ghost;
  return s;
}

/// The particles in each tile of the whole grid (flat, axis 0 fastest); particles outside the grid count
/// nowhere.
template <int Dim, class Kernel>
std::vector<std::int64_t> tile_weights(const GridGeometry<Dim>& whole, const ParticleSet<Dim>& p) {
  std::vector<std::int64_t> weight(whole.tile_count(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!whole.contains(p.x[i])) continue;  // refused by the constructor, with its index
    const IVec<Dim> s = base_layer<Dim, Kernel>(whole, p.x[i], p.half_length(i));
    std::int64_t flat = 0;
    bool inside = true;
    for (int d = Dim - 1; d >= 0; --d) {
      const int t = s[d] >> GridGeometry<Dim>::tile_shift;
      inside = inside && t >= 0 && t < whole.tiles_along(d);
      flat = flat * whole.tiles_along(d) + t;
    }
    if (inside) ++weight[static_cast<std::size_t>(flat)];
  }
  return weight;
}

/// Rank comm.rank()'s box of the bisection weighted by `weight`, cut where the symmetry planes allow
/// (cut_limit).
template <int Dim, class Kernel>
BoxHalo<Dim> boxes_for(const SimulationSpec<Dim>& spec, const GridGeometry<Dim>& whole,
                       const std::vector<std::int64_t>& weight, const Communicator& comm) {
  IVec<Dim> tiles;
  for (int d = 0; d < Dim; ++d) tiles[d] = whole.tiles_along(d);
  std::array<bool, Dim> symmetric_high;
  for (int d = 0; d < Dim; ++d) symmetric_high[d] = spec.boundary.faces[2 * d + 1].type == FaceType::symmetry;
  return BoxHalo<Dim>(
      whole, bisect<Dim>(tiles, weight, comm.size(), cut_limit<Dim>(whole, symmetric_high, Kernel::width)),
      comm.rank(), Kernel::width);
}

/// The division of the grid between the ranks of comm: bisection of the tiles weighted by the particles in
/// them, cut where the symmetry planes allow (cut_limit).
template <int Dim, class Kernel>
BoxHalo<Dim> divide(const SimulationSpec<Dim>& spec, const ParticleSet<Dim>& p, const Communicator& comm) {
  const GridGeometry<Dim> whole = make_geometry<Dim, Kernel>(spec);
  if (comm.size() == 1) return BoxHalo<Dim>(whole);
  for (const FaceCondition<Dim>& f : spec.boundary.faces)
    if (f.type == FaceType::periodic)
      throw InputError(
          "periodic faces run in one process for now (docs/scaling.md); start mpm without mpirun or srun");
  return boxes_for<Dim, Kernel>(spec, whole, tile_weights<Dim, Kernel>(whole, p), comm);
}

}  // namespace detail

template <int Dim, class Kernel>
std::vector<Vec<Dim>> Simulation<Dim, Kernel>::face_reactions() const {
  if (!box_halo_.divided()) return constraints_.reactions();
  return sum_over_ranks<Dim>(constraints_.reaction_sums(), *comm_);
}

template <int Dim, class Kernel>
Real Simulation<Dim, Kernel>::friction_power() const {
  ExactSum power = constraints_.friction_power();
  power.add(rigid_.friction_power());
  for (const auto& pair : contact_.pair_sums()) power.add(pair[Dim + 2]);
  if (!box_halo_.divided()) return power.value();
  return sum_over_ranks({power}, *comm_)[0];
}

template <int Dim, class Kernel>
std::vector<Real> Simulation<Dim, Kernel>::face_contact_spreads() const {
  std::vector<Real> out;
  for (const auto& moments : sum_rows_over_ranks(constraints_.normal_force_moments(), *comm_))
    out.push_back(contact_spread<Dim>(moments));
  return out;
}

template <int Dim, class Kernel>
std::vector<PairForces<Dim>> Simulation<Dim, Kernel>::contact_forces() const {
  std::vector<PairForces<Dim>> out;
  for (const std::array<Real, Dim + 3>& r : sum_rows_over_ranks(contact_.pair_sums(), *comm_)) {
    PairForces<Dim>& f = out.emplace_back();
    for (int d = 0; d < Dim; ++d) f.force[d] = r[d];
    f.normal = r[Dim];
    f.tangential = r[Dim + 1];
    f.friction_power = r[Dim + 2];
  }
  return out;
}

template <int Dim, class Kernel>
std::vector<Vec<Dim>> Simulation<Dim, Kernel>::rigid_reactions() const {
  if (!box_halo_.divided() || rigid_.empty()) return rigid_.reactions();
  return sum_over_ranks<Dim>(rigid_.reaction_sums(), *comm_);
}

template <int Dim, class Kernel>
std::vector<std::size_t> Simulation<Dim, Kernel>::not_owned(std::vector<int>* owner) const {
  std::vector<std::size_t> out;
  const ParticleSet<Dim>& p = particles_;
  for (std::size_t i = 0; i < p.size(); ++i) {
    // Particles beyond an outflow face stay until the next removal counts and erases them (remove_outflow).
    if (box_halo_.surely_owned(p.x[i]) || grid_.geometry.beyond_outflow(p.x[i])) continue;
    const int r =
        box_halo_.owner(detail::base_layer<Dim, Kernel>(box_halo_.whole(), p.x[i], p.half_length(i)));
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
  // A particle that moved less than a tile goes to a neighbour (BoxHalo::peers), and then every rank
  // exchanges with its neighbours only; after a new division, or a step longer than a tile, with every rank.
  const std::vector<int>& peers = box_halo_.peers();
  bool near = true;
  for (int r : owner) near = near && std::binary_search(peers.begin(), peers.end(), r);
  const bool everywhere = comm_->max(near ? 0.0 : 1.0) > 0;
  std::vector<std::vector<std::byte>> to(everywhere ? static_cast<std::size_t>(comm_->size()) : peers.size());
  const PackedArrays with{.state = neo_hookean_.empty(),
                          .affine = spec_.transfer == Transfer::apic,
                          .corners = moves_corners<Kernel>,
                          .half_lengths = reads_half_lengths<Kernel>};
  for (std::size_t k = 0; k < leaving.size(); ++k) {
    const auto to_rank =
        everywhere ? owner[k] : std::lower_bound(peers.begin(), peers.end(), owner[k]) - peers.begin();
    pack_particle(particles_, leaving[k], with, to[static_cast<std::size_t>(to_rank)]);
  }
  if (!leaving.empty()) erase(leaving);
  const std::vector<std::vector<std::byte>> from =
      everywhere ? comm_->exchange(to) : comm_->exchange_with(peers, to);
  const std::size_t first = particles_.size();
  for (const std::vector<std::byte>& bytes : from) unpack_particles(bytes, with, particles_);
  if (particles_.size() == first) return;
  size_rates();
  tiles_changed_ = true;  // settle() sorts them into the scatter order
  if (!stencils_current_) return;
  // The particles that stayed keep their stencils; those that arrived are located here.
  const NodeLayout<Dim> layout(grid_.geometry);
  stencils_.resize(particles_.size());
  for (std::size_t i = first; i < particles_.size(); ++i)
    stencils_[i] = make_stored_stencil<Dim, Kernel>(grid_.geometry, layout, particles_.x[i],
                                                    domain_of<Dim, Kernel>(particles_, i));
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::check(ParticleFault fault, Real dt) {
  const ParticleSet<Dim>& p = particles_;
  if (!box_halo_.divided()) {
    if (!fault) return;
    failed_particle_ = p.id[static_cast<std::size_t>(fault.index)];
    throw SimulationFailure(failure_message(static_cast<std::size_t>(fault.index), dt));
  }
  // Every rank learns of the failure: the one holding the faulty particle of least id says why.
  constexpr std::int64_t none = std::numeric_limits<std::int64_t>::max();
  const std::int64_t mine = fault ? p.id[static_cast<std::size_t>(fault.index)] : none;
  const std::int64_t first = comm_->min(mine);
  if (first == none) return;
  failed_particle_ = first;
  const int root = static_cast<int>(comm_->min(mine == first ? comm_->rank() : comm_->size()));
  const std::string mine_text =
      mine == first ? failure_message(static_cast<std::size_t>(fault.index), dt) : "";
  throw SimulationFailure(broadcast_text(*comm_, mine_text, root));
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::rebalance() {
  std::vector<std::int64_t> counts(static_cast<std::size_t>(comm_->size()), 0);
  counts[static_cast<std::size_t>(comm_->rank())] = static_cast<std::int64_t>(particles_.size());
  comm_->sum(counts);
  std::int64_t total = 0, largest = 0;
  for (std::int64_t n : counts) total += n, largest = std::max(largest, n);
  const double measured = total > 0 ? static_cast<double>(largest) * static_cast<double>(counts.size()) /
                                          static_cast<double>(total)
                                    : 1.0;
  if (measured <= spec_.rebalance_above || steps_ - last_rebalance_step_ < spec_.rebalance_interval) return;
  last_rebalance_step_ = steps_;
  BoxHalo<Dim> next = divide_by_particles();
  if (next.boxes() == box_halo_.boxes()) return;  // the bisection finds no better division
  use_box(std::move(next));
  migrate();  // to the new boxes' owners
  ++rebalances_;
}

template <int Dim, class Kernel>
BoxHalo<Dim> Simulation<Dim, Kernel>::divide_by_particles() const {
  std::vector<std::int64_t> weight = detail::tile_weights<Dim, Kernel>(box_halo_.whole(), particles_);
  comm_->sum(weight);
  return detail::boxes_for<Dim, Kernel>(spec_, box_halo_.whole(), weight, *comm_);
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::adopt_particles() {
  size_rates();
  stencils_current_ = false;
  tiles_changed_ = true;
  if (box_halo_.divided()) {
    use_box(divide_by_particles());
    migrate();
  }
  settle();
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::use_box(BoxHalo<Dim> box) {
  box_halo_ = std::move(box);
  grid_ = Grid<Dim>(box_halo_.box());
  contact_fields_.assign(static_cast<std::size_t>(contact_.fields() - 1), grid_);
  if (!contact_positions_.empty())
    contact_positions_.assign(static_cast<std::size_t>(contact_.fields()), grid_);
  periodic_halo_ = PeriodicHalo<Dim>(grid_.geometry);
  KinematicConstraints<Dim> constraints(spec_.boundary, grid_.geometry, box_halo_.owned_layers());
  constraints.keep_reactions(constraints_);  // the step's, not yet reported
  constraints_ = std::move(constraints);
  order_ = ScatterOrder<Dim>(grid_.geometry, Kernel::width);
  stencils_current_ = false;  // located again in the new box, and sorted into its scatter order
  tiles_changed_ = true;
  if (!mirror_copies_.empty()) {
    mirror_copies_.assign(grid_.size(), 1);
    constraints_.count_mirror_copies(mirror_copies_);
  }
}

}  // namespace mpm

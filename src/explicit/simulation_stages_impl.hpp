#pragma once
// The stages of Simulation<Dim, Kernel>'s step shared by its integrators: locating and ordering the
// particles, P2G with the halo sum, G2P with the stress update, the loads and their power, the failure
// message. Included by simulation_impl.hpp.
#include <algorithm>
#include <optional>
#include <sstream>
#include <string>

#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/reorder.hpp"
#include "mpm/particles/validate.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/g2p_stress.hpp"
#include "mpm/transfer/p2g.hpp"
#include "simulation_stress_impl.hpp"

namespace mpm {

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::settle() {
  if (!stencils_current_)
    tiles_changed_ =
        mpm::build_stencils<Dim, Kernel>(particles_, grid_.geometry, stencils_) || tiles_changed_;
  // The scatter order depends only on the tiles, so it is rebuilt only when a particle changed tile; the
  // particles are then stored in that order, so that the transfers read them in sequence.
  if (tiles_changed_) {
    order_.build(StencilTiles<Dim, Kernel>{stencils_}, particles_.id, particles_.field, contact_.fields());
    if (!order_.identity()) {
      reorder_particles(particles_, order_.order(), reorder_buffer_, stencils_);
      order_.reordered();
    }
  }
  stencils_current_ = true;
  tiles_changed_ = false;
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::prepare_step() {
  located_half_lengths_.clear();  // those of a step that stopped (the storage stays for the next)
  settle();
  evaluate_body_force();
  if (loads_) {
    v_start_ = particles_.v;
    const StencilTiles<Dim, Kernel> tiles{stencils_};
    start_tile_.resize(tiles.size());
    for (std::size_t i = 0; i < tiles.size(); ++i) start_tile_[i] = tiles[i];
  }
  if (!rigid_.empty()) {
    std::ostringstream when;
    when.precision(9);
    when << "step " << steps_ + 1 << ", t = " << time_;
    rigid_.template locate<Kernel>(grid_.geometry, when.str(), box_halo_.owned_layers());
  }
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::keep_located_half_lengths() {
  if constexpr (weighs_half_lengths<Kernel>) {
    if (particles_.half_lengths != HalfLengths::deformed) return;
    located_half_lengths_.resize(particles_.size());
    parallel_for(static_cast<std::ptrdiff_t>(particles_.size()),
                 [&](std::ptrdiff_t i) { located_half_lengths_[i] = particles_.half_length(i); });
  }
}

template <int Dim, class Kernel>
template <Scatter what>
void Simulation<Dim, Kernel>::scatter() {
  if constexpr (what.volume_gradient)  // only contact reads it
    if (!contact_.active())
      return scatter<Scatter{.mass_momentum = what.mass_momentum, .force = what.force}>();
  const std::vector<Grid<Dim>*> fields = field_grids();
  for (int k = 0; k < contact_.fields(); ++k) {
    Grid<Dim>& grid = *fields[k];
    std::optional<FaceTileSums<Dim>> kept;  // a divided grid's: the sums of its face tiles for the halo sum
    if (box_halo_.divided()) kept.emplace(grid.geometry, order_);
    p2g<what>(particles_, stencils(), order_, body_accel_, grid, KeepFaceTiles<Dim>(kept), k,
              has_material_state(), affine(), surface_.empty() ? nullptr : &surface_);
    if (kept)  // the halo sum: the sums of tiles of other boxes at the nodes they share
      box_halo_.sum(grid, kept->take(), what.mass_momentum, what.force, *comm_, nullptr,
                    what.volume_gradient);
    if constexpr (what.force && Dim == 2)  // the hoop force in a pass of its own, as in the implicit step
      if (axisymmetric_) scatter_hoop_force(grid, k);
    if constexpr (what.mass_momentum) periodic_halo_.sum_into_owners(grid, NodeFields::mass_momentum);
    if constexpr (what.volume_gradient) periodic_halo_.sum_into_owners(grid, &GridNode<Dim>::v_new);
    if constexpr (what.force) periodic_halo_.sum_into_owners(grid, NodeFields::force);
    if constexpr (what.mass_momentum) constraints_.fold_and_mirror(grid, NodeFields::mass_momentum);
    if constexpr (what.volume_gradient) constraints_.fold_and_mirror(grid, &GridNode<Dim>::v_new);
    if constexpr (what.force) constraints_.fold_and_mirror(grid, NodeFields::force);
  }
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::scatter_hoop_force(Grid<Dim>& grid, int field) requires(Dim == 2) {
  const HoopForce hoop{particles_.V, particles_.state.sigma, particles_.x};
  std::optional<FaceTileSums<Dim>> kept;
  if (box_halo_.divided()) {
    // Onto the forces the halo sum just agreed: a shared node starts from them again, as one process's pass
    // does.
    hoop_base_.resize(grid.size());
    for (std::size_t n = 0; n < grid.size(); ++n) hoop_base_[n] = grid.nodes[n].a;
    kept.emplace(grid.geometry, order_);
  }
  p2g_add_keeping(KeepFaceTiles<Dim>(kept), stencils(), order_, field, grid, hoop);
  if (kept) box_halo_.sum(grid, kept->take(), false, true, *comm_, &hoop_base_);
}

template <int Dim, class Kernel>
template <Gather what>
void Simulation<Dim, Kernel>::gather(NodeVelocity<Dim> v_grid, Real dt) {
  StencilTargets<Dim, Kernel> next{stencils_};
  StencilTargets<Dim, Kernel>* targets = what.position ? &next : nullptr;
  ParticleFault fault;
  const std::vector<Grid<Dim>*> fields = field_grids();
  for (int k = 0; k < contact_.fields(); ++k) {  // each field's particles from its own grid
    periodic_halo_.copy_to_ghosts(*fields[k]);
    const std::optional<ParticleRange> range =
        contact_.active() ? std::optional<ParticleRange>(order_.field_range(k)) : std::nullopt;
    VelocityBlend<Dim> blend;
    if constexpr (what.velocity) {             // from the stencils before G2P moves the particles
      if (spec_.transfer == Transfer::apic) {  // PIC's velocity and the affine matrices
        g2p_affine(stencils(), *fields[k], v_grid, pic_velocity_, particles_.B, range);
        blend = {0, &pic_velocity_};
      } else if (spec_.flip_fraction < 1) {  // PIC's velocity
        g2p_interpolate(stencils(), *fields[k], v_grid, pic_velocity_, range);
        blend = {spec_.flip_fraction, &pic_velocity_};
      }
    }
    if constexpr (what.position &&
                  moves_corners<Kernel>)  // CPDI2: the corners, from the stencils of the step's start
      g2p_corners(stencils(), *fields[k], v_grid, dt, particles_.corners, particles_.corners, range);
    // A deforming pass through the rate-form policy of the table (LaneStress: compiled once per dimension).
    const auto deform = [&]<class Policy>(const Policy& policy) {
      return g2p<what>(particles_, stencils(), *fields[k], v_grid, dt,
                       LaneStress<Dim, Policy::reads_velocity>(policy), targets, range, blend);
    };
    ParticleFault f;
    if constexpr (!what.deformation) {
      f = g2p<what>(particles_, stencils(), *fields[k], v_grid, dt, NoStress{}, targets, range, blend);
    } else if (!neo_hookean_.empty()) {
      f = g2p<what>(particles_, stencils(), *fields[k], v_grid, dt, NeoHookeanLanes<Dim>{neo_hookean_},
                    targets, range, blend);
    } else if (axisymmetric_) {
      if constexpr (Dim == 2) {  // axisymmetry is 2-D: the other dimensions compile no such pass
        if (!drucker_prager_.empty())
          f = deform(DruckerPragerLanes<Dim, true>{spec_.materials, drucker_prager_, dt});
        else
          f = deform(RecordRates<Dim, true>{grad_v_, hoop_rate_});
      }
    } else if (!drucker_prager_.empty()) {
      f = deform(DruckerPragerLanes<Dim, false>{spec_.materials, drucker_prager_, dt});
    } else {
      f = deform(RecordRates<Dim, false>{grad_v_, hoop_rate_});
    }
    fault.index = std::min(fault.index, f.index);
  }
  if (neo_hookean_.empty() && drucker_prager_.empty()) {
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
void Simulation<Dim, Kernel>::account_load_power(Real dt) {
  // Grouped by the tiles of the step's start, whose particles one rank held, in id order.
  const ParticleSet<Dim>& p = particles_;
  load_power_ = exact_particle_sum<1>(
      p.size(), [&](std::size_t i) { return start_tile_[i]; },
      [&](std::size_t i) {
        return std::array<Real, 1>{particle_load_power(p, i, spec_.gravity, body_accel_, v_start_) +
                                   surface_.work(p, i, grid_.geometry) / dt};
      },
      *comm_)[0];
}

template <int Dim, class Kernel>
void Simulation<Dim, Kernel>::evaluate_body_force() {
  if (spec_.body_force) {
    body_accel_.resize(particles_.size());
    parallel_for(static_cast<std::ptrdiff_t>(particles_.size()),
                 [&](std::ptrdiff_t i) { body_accel_[i] = spec_.body_force(particles_.X[i], time_); });
  }
  if (spec_.surface_loads.empty()) return;
  surface_.reset(particles_);
  spec_.surface_loads.add_to_particles(particles_, time_, 1, spec_.geometry,
                                       surface_);  // at the step's start
  surface_.start(particles_);
}

template <int Dim, class Kernel>
std::string Simulation<Dim, Kernel>::failure_message(std::size_t i, Real dt) const {
  const ParticleSet<Dim>& p = particles_;
  const Real J = p.F[i].determinant();
  std::string cause;
  if (!p.x[i].allFinite() || !p.v[i].allFinite() || !std::isfinite(J))
    cause = "non-finite position, velocity or deformation gradient";
  else if (!grid_.geometry.contains(p.x[i]))
    cause = "left the grid at " + format_point<Dim>(p.x[i]);
  else if (!(J > 0))
    cause = "det F = " + format_number(J) + " <= 0 (material inverted)";
  else if (!p.state.empty() && !(p.state.stretch3[i] > 0 && p.V[i] > 0))
    cause = "volume V / V0 = " + format_number(p.V[i] / p.V0[i]) + " with out-of-plane stretch " +
            format_number(p.state.stretch3[i]) + " (material inverted)";
  else if (!p.state.empty() && !p.state.sigma[i].full().allFinite())
    cause = "non-finite stress from the material update";
  else if (moves_corners<Kernel>)
    cause = "its CPDI2 domain folded (the Jacobian of its corners' map <= 0 at a corner)";
  else
    cause = "non-finite stress from the material update";
  std::ostringstream os;
  os.precision(9);
  os << "step " << steps_ + 1 << ", t = " << time_ + dt << ": particle " << p.id[i] << ": " << cause;
  return os.str();
}

template <int Dim, class Kernel>
double Simulation<Dim, Kernel>::bytes_per_particle() const {
  const double n = static_cast<double>(particles_.size());
  // The optional arrays by what they hold (a dropped array that kept its storage shows).
  return static_cast<double>(particles_.bytes_per_particle(false)) + sizeof(StencilT) +
         static_cast<double>(
             particles_.l0.capacity() * sizeof(Vec<Dim>) +
             located_half_lengths_.capacity() * sizeof(Vec<Dim>) + order_.bytes() +
             body_accel_.capacity() * sizeof(Vec<Dim>) + surface_.bytes() +
             grid_.bytes() * contact_.fields() +
             (particles_.state.empty() ? 0 : particles_.size() * MaterialState::bytes_per_particle()) +
             grad_v_.capacity() * sizeof(Mat<Dim>) + hoop_rate_.capacity() * sizeof(Real) +
             pic_velocity_.capacity() * sizeof(Vec<Dim>) + particles_.B.capacity() * sizeof(Mat<Dim>) +
             particles_.corners.capacity() * sizeof(Corners<Dim>) + reorder_buffer_.bytes()) /
             n;
}

}  // namespace mpm

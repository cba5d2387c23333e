#pragma once
// Implementation of ImplicitSimulation<Dim, Kernel>; included by the per-dimension instantiation files.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>

#include "consistent_mass_impl.hpp"
#include "mpm/boundary/rigid_bodies_locate.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/core/time_step.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/materials/material_step.hpp"
#include "mpm/particles/stable_step.hpp"
#include "mpm/particles/validate.hpp"
#include "mpm/transfer/particle_update.hpp"
#include "projection_impl.hpp"
#include "residual_impl.hpp"
#include "tangent_impl.hpp"

namespace mpm {

/// The discrete momentum equation of one step as a NonlinearProblem over the free nodal unknowns.
template <int Dim, class Kernel>
class ImplicitSimulation<Dim, Kernel>::Residual final : public numerics::NonlinearProblem {
 public:
  Residual(ImplicitSimulation& sim, Real dt) : sim_(sim), dt_(dt) {}
  Eigen::Index size() const override { return static_cast<Eigen::Index>(sim_.dof_node_.size()); }
  bool residual(const Eigen::VectorXd& x, Eigen::VectorXd& r) override { return sim_.residual_at(x, dt_, r); }
  bool precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) override {
    if (!sim_.tangent_ || !sim_.tangent_->factorised)
      z = r;  // a singular tangent: go on unpreconditioned
    else
      z = sim_.tangent_->lu.solve(r);
    return true;
  }
  bool refresh_preconditioner(const Eigen::VectorXd& x, const Eigen::VectorXd& /*fx*/) override {
    return sim_.factorise_tangent(x, dt_);
  }

 private:
  ImplicitSimulation& sim_;
  Real dt_;
};

template <int Dim, class Kernel>
ImplicitSimulation<Dim, Kernel>::ImplicitSimulation(const ImplicitSpec<Dim>& spec, ParticleSet<Dim> particles)
    : spec_((validate(spec), spec)),
      particles_(std::move(particles)),
      grid_(GridGeometry<Dim>{spec.grid_lo,
                              spec.h,
                              spec.cells,
                              Kernel::ghost,
                              {},
                              periodic_axes(spec.boundary),
                              outflow_faces(spec.boundary),
                              wall_faces(spec.boundary),
                              clamped_faces(spec.kernel, spec.boundary)}),
      periodic_halo_(grid_.geometry),
      constraints_(spec.boundary, grid_.geometry),
      layout_(grid_.geometry),
      order_(grid_.geometry, Kernel::width),
      rigid_(spec.rigid_bodies, grid_.geometry, face_types(spec.boundary)) {
  dashpots_ = constraints_.dashpots();
  ParticleSet<Dim>& p = particles_;
  p.half_lengths = half_lengths_of(spec.kernel);
  p.max_half_length = max_half_length(spec.kernel) * spec.h;
  const GridGeometry<Dim>& g = grid_.geometry;
  if (p.size() == 0) throw InputError("particles: the simulation has no particles");
  if (p.state.empty()) p.state.resize(p.size());  // a state the particles bring (a geostatic stress) is kept
  if (spec.transfer == Transfer::apic)
    p.B.assign(p.size(), Mat<Dim>::Zero());               // the particles start unsheared
  if constexpr (moves_corners<Kernel>) place_corners(p);  // CPDI2's domains start as CPDI's
  const bool axisymmetric = Dim == 2 && spec_.geometry == Geometry::axisymmetric;
  const Real min_mass = start_particles(p, spec_.materials, spec_.kernel, g, axisymmetric, 1);
  for (std::size_t i = 0; i < p.size(); ++i)  // the Neo-Hookean stress of F and its stored energy V0 W(F)
    if (const auto* law = std::get_if<NeoHookean>(&spec_.materials[p.material[i]])) {
      const Real J = p.F[i].determinant();
      p.state.sigma[i] = neo_hookean_stress<Dim>(*law, law->template stress<Dim>(p.F[i], J), J);
      p.state.energy[i] = p.V0[i] * law->template energy_density<Dim>(p.F[i], J);
    }
  min_node_mass_ = 1e-14 * min_mass;
  start_internal_state(spec_.materials, p.material, p.state);
  if constexpr (!reads_half_lengths<Kernel>) p.drop_half_lengths();  // read by no stage
  for (const Material& m : spec_.materials) modulus_ = std::max(modulus_, young_modulus(m));
  face_reactions_.assign(constraints_.names().size(), Vec<Dim>::Zero());
  mirrored_.assign(grid_.size(), 0);
  constraints_.mark_mirrored(mirrored_);
  periodic_halo_.for_each_image([&](std::int32_t image, std::int32_t) { mirrored_[image] = 1; });
  const std::size_t nodes = grid_.size();
  f_k_.assign(nodes, Vec<Dim>::Zero());
  f_ext_.assign(nodes, Vec<Dim>::Zero());
  f_trial_.assign(nodes, Vec<Dim>::Zero());
  momentum_velocity_.assign(nodes, Vec<Dim>::Zero());
  // The explicit reference step: fixed, or the CFL condition on the dilatational wave speed.
  explicit_dt_ = spec_.step.dt > 0
                     ? spec_.step.dt
                     : cfl_step(spec_.step.cfl, spec_.h, fastest_signal(particles_, spec_.materials));
  dt_ = explicit_dt_ * std::min(spec_.step.start_factor, spec_.step.step_factor);
}

template <int Dim, class Kernel>
Real ImplicitSimulation<Dim, Kernel>::residual_scale(Real dt) const {
  return spec_.scaled_residual ? 1 / (modulus_ * std::pow(spec_.h, Dim) * dt)
                               : 1;  // Sulsky & Kaul 2004, Sec. 3.2.2
}

template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::restore(Real time, std::int64_t steps, Real dt,
                                              const ImplicitCounters& counters,
                                              const std::vector<Vec<Dim>>& rigid_displacement) {
  time_ = time;
  steps_ = steps;
  dt_ = dt;
  counters_ = counters;
  rigid_.restore(rigid_displacement);
}

template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::run_until(Real t_end) {
  while (time_ < t_end * (1 - 1e-14)) step(t_end - time_);
}

template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::remove_outflow() {
  const std::vector<std::size_t> gone = beyond_outflow(particles_, grid_.geometry);
  for (std::size_t i : gone) outflow_.add(particles_, i, particles_.state.energy[i]);
  if (!gone.empty()) erase_particles(particles_, gone);  // the next projection locates the rest again
}

template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::step(Real max_dt) {
  remove_outflow();
  Real dt = std::min(dt_, max_dt);
  // A step that would leave less than 1e-6 of itself to max_dt (the end time, reached through sums of rounded
  // steps) takes that sliver along: a sliver step's residual, divided by its dt, would be round-off.
  if (max_dt > dt && max_dt - dt < 1e-6 * dt) dt = max_dt;
  check_step_advances(steps_, time_, dt);
  bool halved = false;
  attempts_.clear();
  for (int retry = 0; !try_step(dt); ++retry) {
    if (retry == spec_.step.max_retries) {
      std::ostringstream os;
      os.precision(9);
      os << "step " << steps_ + 1 << ", t = " << time_ << ": the implicit solve failed with dt = " << dt
         << " after " << retry << " halvings of the step";
      throw SimulationFailure(os.str());
    }
    ++counters_.retries;
    dt *= 0.5;
    halved = true;
  }
  time_ += dt;
  ++steps_;
  // Grow toward the target step (Sulsky & Kaul 2004, footnotes of Tables 1-6), from the halved step after a
  // retry.
  if (halved) dt_ = dt;
  dt_ = std::min(spec_.step.step_factor * explicit_dt_, dt_ * spec_.step.growth);
}

// One step (Sulsky & Kaul 2004, Secs 2.3-2.4): project the particles, solve the theta-blended momentum
// equation for the free nodal unknowns, then update the particles from the converged solution.
template <int Dim, class Kernel>
bool ImplicitSimulation<Dim, Kernel>::try_step(Real dt) {
  attempts_.push_back({dt, {}});
  project(dt);
  build_dofs(time_ + dt);
  const bool momentum = spec_.formulation == Formulation::momentum;
  // Initial guess: the projected velocity (or momentum) at t^k.
  Eigen::VectorXd x(static_cast<Eigen::Index>(dof_node_.size()));
  for (std::size_t k = 0; k < dof_node_.size(); ++k) {
    const GridNode<Dim>& node = grid_.nodes[dof_node_[k]];
    x[static_cast<Eigen::Index>(k)] = (momentum ? node.m : 1.0) * node.v[dof_comp_[k]];
  }
  Residual problem(*this, dt);
  Eigen::VectorXd r;
  last_newton_ = 0;
  if (spec_.theta == 0 && !spec_.consistent_mass) {
    // Explicit: the unknowns follow from the forces at t^k (Sulsky & Kaul 2004, Eq. (2.4.4)); one evaluation
    // updates the stress.
    for (std::size_t k = 0; k < dof_node_.size(); ++k) {
      const std::int32_t n = dof_node_[k];
      const int c = dof_comp_[k];
      const Real m = grid_.nodes[n].m;
      x[static_cast<Eigen::Index>(k)] += dt * (f_k_[n][c] + f_ext_[n][c]) / (momentum ? 1.0 : m);
    }
    ++counters_.residual_evaluations;
    if (!residual_at(x, dt, r)) return false;
  } else if (spec_.solver == ImplicitSolver::linear_cg) {
    // One CG solve (Alg. 2) of A s = -F(x0), A s = F(x0 + s) - F(x0).
    Eigen::VectorXd r0;
    if (!residual_at(x, dt, r0)) return false;
    const Eigen::VectorXd x0 = x;
    Eigen::VectorXd s = Eigen::VectorXd::Zero(x.size()), rs;
    bool ok = true;
    const auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& Av) {
      // A failed evaluation ends the CG solve (a non-finite product stops it) and the step is retried.
      if (residual_at(x0 + v, dt, rs))
        Av = rs - r0;
      else
        Av.setConstant(r0.size(), std::numeric_limits<Real>::quiet_NaN()), ok = false;
    };
    if (spec_.frozen_jacobian && !factorise_tangent(x0, dt)) return false;
    const auto pre = [&](const Eigen::VectorXd& v, Eigen::VectorXd& z) { problem.precondition(v, z); };
    const numerics::LinearStats ls = numerics::conjugate_gradient(
        apply, -r0, s, spec_.newton.linear_tolerance, spec_.newton.max_krylov,
        spec_.frozen_jacobian ? std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>(pre)
                              : std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>{});
    counters_.krylov_iterations += ls.iterations;
    counters_.residual_evaluations += ls.iterations + 2;
    x = x0 + s;
    if (!ok || !residual_at(x, dt, r)) return false;
    last_newton_ = 1;
    ++counters_.newton_iterations;
  } else {
    // The frozen-Jacobian preconditioner is built at the initial guess, which then needs no second
    // evaluation.
    const bool preconditioned = spec_.frozen_jacobian || spec_.solver == ImplicitSolver::newton_direct;
    if (preconditioned) {
      ++counters_.residual_evaluations;
      if (!residual_at(x, dt, r) || !factorise_tangent(x, dt)) return false;
    }
    numerics::NewtonSettings settings = spec_.newton;
    settings.krylov = spec_.solver == ImplicitSolver::newton_cg       ? numerics::Krylov::cg
                      : spec_.solver == ImplicitSolver::newton_direct ? numerics::Krylov::direct
                                                                      : numerics::Krylov::gmres;
    settings.precondition = preconditioned;
    const numerics::SolveStats stats = numerics::solve(problem, x, settings, preconditioned ? &r : nullptr);
    counters_.newton_iterations += stats.newton_iterations;
    counters_.krylov_iterations += stats.krylov_iterations;
    counters_.residual_evaluations += stats.residual_evaluations;
    counters_.backtracks += stats.backtracks;
    last_newton_ = stats.newton_iterations;
    attempts_.back().residual_norms = stats.residual_norms;
    if (!stats.converged) return false;
    // The trial state must be that of the solution, not of the last perturbed evaluation.
    if (x.size() != last_x_.size() || x != last_x_) {
      ++counters_.residual_evaluations;
      if (!residual_at(x, dt, r)) return false;
    }
  }
  for (std::uint8_t ok : trial_.ok)
    if (!ok) return false;
  compute_reactions(dt);
  accept(dt);
  return true;
}

// Update the particles from the converged step (Sulsky & Kaul 2004, Eq. (2.3.2), Eq. (2.3.3), Eq. (2.3.4),
// Eq. (2.3.5), or Eq. (3.2.5), Eq. (3.2.6)); with moves_with_projected_velocity the momentum formulation
// moves them with the v^L of Sulsky & Kaul 2004, Eq. (3.2.7), as the velocity formulation does. The new
// positions are checked before anything changes, so a failure leaves the last good state.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::accept(Real dt) {
  ParticleSet<Dim>& p = particles_;
  const bool momentum = spec_.formulation == Formulation::momentum;
  const bool with_momentum = momentum && !moves_with_projected_velocity(spec_);
  const bool axisymmetric = Dim == 2 && spec_.geometry == Geometry::axisymmetric;
  trial_.x.resize(p.size());
  gather_over_active_nodes([&](const GridNode<Dim>& node,
                               std::size_t n) { return with_momentum ? momentum_velocity_[n] : node.v_new; },
                           v_move_);
  // CPDI2: the corners move with the same node velocities, now on GridNode::a (Sadeghirad et al. 2013).
  if constexpr (moves_corners<Kernel>)
    g2p_corners(stencils(), grid_, &GridNode<Dim>::a, dt, p.corners, trial_.corners);
  if (!momentum)
    gather_over_active_nodes([](const GridNode<Dim>& node, std::size_t) { return node.v_new - node.v; }, dv_);
  // PIC's velocity for the blend: sum_i S_ip v_i^L of the solution's node velocities (P_i^L / m_i in the
  // momentum formulation), which v_move_ already is unless the momentum formulation moves with the
  // re-projected velocity.
  const bool blend = spec_.flip_fraction < 1;
  const bool own_pic = blend && momentum && !with_momentum;
  if (own_pic)
    gather_over_active_nodes([&](const GridNode<Dim>&, std::size_t n) { return momentum_velocity_[n]; },
                             pic_velocity_);
  const std::vector<Vec<Dim>>& pic = own_pic ? pic_velocity_ : v_move_;
  // APIC: the velocity and affine matrix of the solution's node velocities (those PIC takes) at the step's
  // start.
  const bool apic = spec_.transfer == Transfer::apic;
  if (apic) {
    put_on_active_nodes([&](const GridNode<Dim>& node, std::size_t n) {
      return momentum ? momentum_velocity_[n] : node.v_new;
    });
    g2p_affine(stencils(), grid_, &GridNode<Dim>::a, pic_velocity_, affine_);
  }
  // The velocity gradient of the solution by entry (Mat is column-major: entry (a, c) is Real a + c Dim).
  const auto gradient = [](const RecordLanes<Mat<Dim>>& L) {
    return [&L](int a, int c) -> const RealLanes& { return L[a + c * Dim]; };
  };
  // Sulsky & Kaul 2004, Eq. (2.3.2), or Eq. (3.2.5), kept to the grid; a CPDI2 particle goes to its corners'
  // centroid, and its corners with it through a wrap or onto a wall (transfer/particle_update.hpp, as the
  // explicit pass). The new positions are checked before anything changes, so a failure leaves the last good
  // state.
  const PositionBounds<Dim> bounds(grid_.geometry);
  std::atomic<std::int64_t> moved_out{ParticleFault::none};
  const std::ptrdiff_t blocks = LaneBlock::count(p.size());
  parallel_for(blocks, [&](std::ptrdiff_t b) {
    const LaneBlock block(b, static_cast<std::ptrdiff_t>(p.size()));
    RecordLanes<Vec<Dim>> x = block.load(p.x);
    [[maybe_unused]] RecordLanes<Corners<Dim>> corners;
    if constexpr (moves_corners<Kernel>) corners = block.load(trial_.corners);  // moved by g2p_corners
    note_first_fault(moved_out, block,
                     move_positions<Dim, Kernel>(bounds, x, block.load(v_move_), dt, corners));
    block.store(trial_.x, x);
    if constexpr (moves_corners<Kernel>) block.store(trial_.corners, corners);
  });
  if (const std::int64_t i = moved_out.load(); i != ParticleFault::none) {
    std::ostringstream os;
    os.precision(9);
    os << "step " << steps_ + 1 << ", t = " << time_ + dt << ": particle " << p.id[i] << " ";
    if (moves_corners<Kernel> &&
        (grid_.geometry.contains(trial_.x[i]) || grid_.geometry.beyond_outflow(trial_.x[i])))
      os << "would fold its CPDI2 domain (the Jacobian of its corners' map <= 0 at a corner)";
    else
      os << "would leave the grid";
    throw SimulationFailure(os.str());
  }
  parallel_for(blocks, [&](std::ptrdiff_t b) {
    const LaneBlock block(b, static_cast<std::ptrdiff_t>(p.size()));
    RecordLanes<Mat<Dim>> F_new;
    RealLanes F[Dim][Dim];
    const RecordLanes<Mat<Dim>> L = block.load(trial_.grad_v);
    const RealLanes J = deform<Dim>(gradient(L), dt, block.load(p.F), F, F_new);
    block.store(p.F, F_new);
    for (int k = 0; k < block.active; ++k) {
      const std::ptrdiff_t i = block.first + k;
      p.x[i] = trial_.x[i];
      if constexpr (moves_corners<Kernel>) p.corners[i] = trial_.corners[i];
      // Sulsky & Kaul 2004, Eq. (2.3.3); else Eq. (3.2.6)
      const Vec<Dim> v_new = momentum ? trial_.v[i] : Vec<Dim>(p.v[i] + dv_[i]);
      p.v[i] = apic    ? pic_velocity_[i]
               : blend ? Vec<Dim>(spec_.flip_fraction * v_new + (1 - spec_.flip_fraction) * pic[i])
                       : v_new;
      if (apic) p.B[i] = affine_[i];
      // The hoop stretch is r / R exactly; the plane-stress thickness stretch accumulates 1 + de_zz.
      particles_.state.stretch3[i] = axisymmetric ? p.x[i][0] / p.X[i][0] : trial_.stretch3[i];
      // V = V0 det F: Sulsky & Kaul 2004, Eq. (2.3.4), rho^L = rho^k / (1 + tr de), in the exact form det(I
      // + de) of which 1 + tr de is the first order.
      p.V[i] = p.V0[i] * J[k] * particles_.state.stretch3[i];
      particles_.state.sigma[i] = trial_.sigma[i];
      particles_.state.eps_bar[i] = trial_.eps_bar[i];
      if (particles_.state.keeps_internal) particles_.state.internal[i] = trial_.internal[i];
      particles_.state.energy[i] += trial_.energy[i];
      const auto* law = std::get_if<ElastoPlastic>(&spec_.materials[p.material[i]]);
      if (law && law->specific_heat > 0)
        particles_.state.temperature[i] +=
            trial_.work[i] / (p.m[i] * law->specific_heat);  // Sulsky & Kaul 2004, Eq. (2.3.5)
    }
  });
  rigid_.advance(time_, dt);
}

}  // namespace mpm

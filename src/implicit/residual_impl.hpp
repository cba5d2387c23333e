#pragma once
// The residual of an implicit step (Sulsky & Kaul 2004, Eq. (2.4.12)): the trial velocities on the nodes,
// the trial stresses and forces, and the reactions of the converged step. Included by
// implicit_simulation_impl.hpp.
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/materials/material_step.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/p2g.hpp"

namespace mpm {

// Put the trial unknowns on the nodes as the Lagrangian velocity v_i^L (in v_new): free components from x,
// prescribed ones from the constraints, mirrored ghosts reflected. In the momentum formulation x holds P_i^L:
// the particle velocities follow from Sulsky & Kaul 2004, Eq. (3.2.6) and v_i^L is their projection,
// Eq. (3.2.7).
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::node_velocity_from(const Eigen::VectorXd& x) {
  const bool momentum = spec_.formulation == Formulation::momentum;
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid_.nodes[n];
    node.v_new = node.v;  // inactive nodes keep v^k (zero)
  });
  for (std::size_t k = 0; k < dof_node_.size(); ++k) {
    GridNode<Dim>& node = grid_.nodes[dof_node_[k]];
    const Real xk = x[static_cast<Eigen::Index>(k)];
    node.v_new[dof_comp_[k]] = momentum ? xk / node.m : xk;
  }
  for (const Fixed& f : fixed_) grid_.nodes[f.node].v_new[f.component] = f.value;
  constraints_.mirror(grid_, &GridNode<Dim>::v_new);
  periodic_halo_.copy_to_ghosts(grid_);
  if (!momentum) return;
  for (std::size_t n = 0; n < grid_.size(); ++n) momentum_velocity_[n] = grid_.nodes[n].v_new;  // P_i^L / m_i
  // v_p^L = v_p^k + sum_i (P_i^L - P_i^k) N_i(x_p) / m_i (Sulsky & Kaul 2004, Eq. (3.2.6): the momentum
  // change is dt times the force), over the nodes that carry mass.
  const ParticleSet<Dim>& p = particles_;
  gather_over_active_nodes([&](const GridNode<Dim>& node, std::size_t) { return node.v_new - node.v; }, dv_);
  trial_.v.resize(p.size());
  parallel_for(static_cast<std::ptrdiff_t>(p.size()),
               [&](std::ptrdiff_t i) { trial_.v[i] = p.v[i] + dv_[i]; });
  scatter_momentum(trial_.v);  // the momentum P^L into v_new
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) {
    momentum_to_velocity(grid_.nodes[n].v_new, grid_.nodes[n].m, min_node_mass_);
  });
  for (const Fixed& f : fixed_) grid_.nodes[f.node].v_new[f.component] = f.value;
  constraints_.mirror(grid_, &GridNode<Dim>::v_new);
  periodic_halo_.copy_to_ghosts(grid_);
}

// F(x) of Sulsky & Kaul 2004, Eq. (2.4.12), in the form (P^L - P^k) - dt ((1 - theta) f^k + theta f^L +
// f^ext) on the free unknowns (P^L = m v^L in the velocity formulation, Sulsky & Kaul 2004, Eq. (2.4.5);
// Eq. (3.2.4) in the momentum one; P^L - P^k = M (v^L - v^k) with the consistent mass of Eq. (2.2.6)),
// divided by Y h^Dim dt (Sec. 3.2.2). The stress follows from the strain increments of v^L (Sulsky & Kaul
// 2004, Eq. (2.2.18), Eq. (2.2.19), Eq. (2.2.20), Eq. (2.2.21)).
template <int Dim, class Kernel>
bool ImplicitSimulation<Dim, Kernel>::residual_at(const Eigen::VectorXd& x, Real dt, Eigen::VectorXd& r) {
  last_x_ = x;
  node_velocity_from(x);
  if (spec_.consistent_mass) consistent_inertia();
  const ParticleSet<Dim>& p = particles_;
  const std::size_t np = p.size();
  Trial& t = trial_;
  t.sigma.resize(np);
  t.eps_bar.resize(np);
  t.work.resize(np);
  t.energy.resize(np);
  t.stretch3.resize(np);
  t.internal.resize(p.state.keeps_internal ? np : 0);
  t.grad_v.resize(np);
  t.ok.resize(np);
  t.v_r.resize(np);
  // grad v_p = sum_i v_i^L (x) grad N_i(x_p), whose symmetric part times dt is the strain increment of Sulsky
  // & Kaul 2004, Eq. (2.2.18), Eq. (2.2.19), Eq. (2.2.20), and the radial velocity sum_i N_i(x_p) v_ri^L;
  // stored as column-major records, as Mat is.
  g2p_gather<Sums{.acceleration = false, .velocity = true, .gradient = true}>(
      stencils(), grid_, &GridNode<Dim>::v_new, ParticleRange{0, static_cast<std::ptrdiff_t>(np)},
      [&](const LaneBlock& block, const GatheredLanes<Dim>& sum) {
        RecordLanes<Mat<Dim>> L;
        for (int a = 0; a < Dim; ++a)
          for (int c = 0; c < Dim; ++c) L[a + c * Dim] = sum.grad_v[a][c];
        block.store(t.grad_v, L);
        block.store(t.v_r, {sum.v[0]});
      });
  const Geometry geometry = Dim == 2 ? spec_.geometry : Geometry::plane_strain;
  parallel_for(static_cast<std::ptrdiff_t>(np), [&](std::ptrdiff_t i) {
    const MaterialState& state = p.state;
    const MaterialStep u =
        material_step<Dim>(spec_.materials[p.material[i]], state.sigma[i], state.eps_bar[i],
                           state.stretch3[i], state.internal_at(i), p.V[i], p.V0[i], p.F[i], dt * t.grad_v[i],
                           dt, geometry == Geometry::axisymmetric ? dt * t.v_r[i] / p.x[i][0] : 0, geometry);
    t.ok[i] = u.ok;
    t.sigma[i] = u.sigma;
    t.eps_bar[i] = u.eps_bar;
    t.work[i] = u.work;
    t.energy[i] = u.energy;
    t.stretch3[i] = u.stretch3;
    if (state.keeps_internal) t.internal[i] = u.internal;
  });
  for (std::size_t i = 0; i < np; ++i)
    if (!t.ok[i]) return false;
  scatter_force(t.sigma, f_trial_);
  const Real scale = residual_scale(dt);
  const Real theta = spec_.theta;
  r.resize(x.size());
  for (std::size_t k = 0; k < dof_node_.size(); ++k) {
    const std::int32_t n = dof_node_[k];
    const int c = dof_comp_[k];
    const GridNode<Dim>& node = grid_.nodes[n];
    const Real P_L = spec_.formulation == Formulation::momentum ? x[static_cast<Eigen::Index>(k)]
                                                                : node.m * x[static_cast<Eigen::Index>(k)];
    const Real dP = spec_.consistent_mass ? mass_dv_[n][c] : P_L - node.m * node.v[c];
    // An absorbing face's dashpot -Z A v^L, at the end of the step as in the explicit update (Lysmer &
    // Kuhlemeyer 1969).
    const Real force =
        (1 - theta) * f_k_[n][c] + theta * f_trial_[n][c] + f_ext_[n][c] - dof_resistance_[k] * node.v_new[c];
    r[static_cast<Eigen::Index>(k)] = scale * (dP - dt * force);
  }
  return r.allFinite();
}

// The force each constraint applied: the momentum equation's imbalance on its prescribed components,
// (m_i v_i^L - m_i v_i^k)/dt - ((1 - theta) f^k + theta f^L + f^ext); an absorbing face's, its dashpots' -Z A
// v^L.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::compute_reactions(Real dt) {
  const int groups = static_cast<int>(face_reactions_.size());
  for (Vec<Dim>& f : face_reactions_) f.setZero();
  std::vector<Vec<Dim>>& rigid_reactions = rigid_.reactions();
  for (Vec<Dim>& f : rigid_reactions) f.setZero();
  const Real theta = spec_.theta;
  for (const Fixed& f : fixed_) {
    const GridNode<Dim>& node = grid_.nodes[f.node];
    const int c = f.component;
    const Real inertia = spec_.consistent_mass ? mass_dv_[f.node][c] : node.m * (f.value - node.v[c]);
    const Real force =
        inertia / dt - ((1 - theta) * f_k_[f.node][c] + theta * f_trial_[f.node][c] + f_ext_[f.node][c]);
    (f.owner < groups ? face_reactions_[f.owner] : rigid_reactions[f.owner - groups])[c] += force;
  }
  for (const auto& d : dashpots_)  // the dashpots' force on the free components they hold
    if (d.owned && grid_.nodes[d.node].m > min_node_mass_)
      face_reactions_[d.group][d.component] -= d.resistance * grid_.nodes[d.node].v_new[d.component];
}

}  // namespace mpm

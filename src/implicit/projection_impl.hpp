#pragma once
// The grid side of an implicit step (Sulsky & Kaul 2004, Sec. 2.3.1): the projection of the particles, the
// unknowns, and the scatters of momentum, internal and body forces. Included by implicit_simulation_impl.hpp.
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/p2g.hpp"

namespace mpm {

// Initialisation phase (Sulsky & Kaul 2004, Sec. 2.3.1): lumped mass (Sulsky & Kaul 2004, Eq. (2.2.12)),
// momentum (Sulsky & Kaul 2004, Eq. (2.2.14) or Eq. (3.2.3)), internal force at t^k (Sulsky & Kaul 2004,
// Eq. (2.4.6)) and external force; rigid-body stencils at their positions.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::project(Real dt) {
  if (build_stencils<Dim, Kernel>(particles_, grid_.geometry, stencils_))
    order_.build(StencilTiles<Dim, Kernel>{stencils_}, particles_.id);
  p2g<Scatter{.mass_momentum = true, .force = false}>(particles_, stencils(), order_, {}, grid_,
                                                      KeepNothing{}, 0, false,
                                                      affine());  // as explicit
  periodic_halo_.sum_into_owners(grid_, NodeFields::mass_momentum);
  constraints_.fold_and_mirror(grid_, NodeFields::mass_momentum);
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid_.nodes[n];
    node_velocity(node, min_node_mass_);
    f_ext_[n] = node.m * spec_.gravity;
  });
  scatter_force(particles_.state.sigma, f_k_);
  if (spec_.body_force || !spec_.surface_loads.empty()) add_body_force(dt);
  if (spec_.consistent_mass) project_consistent(dt);
  if (!rigid_.empty()) {
    std::ostringstream when;
    when.precision(9);
    when << "step " << steps_ + 1 << ", t = " << time_ + dt;
    rigid_.template locate<Kernel>(grid_.geometry, when.str());
  }
}

// The unknowns: components of nodes that carry mass, minus those a face constraint or a rigid body prescribes
// (Sulsky & Kaul 2004, Sec. 2.4.1: nodes with displacement conditions are excluded) and mirrored ghosts.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::build_dofs(Real t_new) {
  const std::size_t nodes = grid_.size();
  std::vector<Real> value(nodes * Dim, 0);
  std::vector<int> owner(nodes * Dim, -1);
  const std::vector<Vec<Dim>> face_velocity = constraints_.velocities(t_new);
  for (const auto& c : constraints_.components()) {
    owner[c.node * Dim + c.component] = c.group;
    value[c.node * Dim + c.component] = face_velocity[c.group][c.component];
  }
  const int groups = static_cast<int>(face_velocity.size());
  for (std::size_t b = 0; b < rigid_.size(); ++b) {
    const Vec<Dim> v = rigid_.bodies()[b].velocity(t_new);
    for (std::int32_t n : rigid_.nodes(b))
      for (int c = 0; c < Dim; ++c) {
        if (!rigid_.bodies()[b].imposes[c]) continue;
        owner[n * Dim + c] = groups + static_cast<int>(b);
        value[n * Dim + c] = v[c];
      }
  }
  std::vector<Real> resistance(nodes * Dim, 0);
  for (const auto& d : dashpots_) resistance[d.node * Dim + d.component] += d.resistance;
  dof_node_.clear();
  dof_comp_.clear();
  dof_resistance_.clear();
  fixed_.clear();
  for (std::size_t n = 0; n < nodes; ++n) {
    if (mirrored_[n]) continue;
    for (int c = 0; c < Dim; ++c) {
      const std::size_t k = n * Dim + c;
      if (owner[k] >= 0)
        fixed_.push_back({static_cast<std::int32_t>(n), c, owner[k], value[k]});
      else if (grid_.nodes[n].m > min_node_mass_) {
        dof_node_.push_back(static_cast<std::int32_t>(n));
        dof_comp_.push_back(static_cast<std::int8_t>(c));
        dof_resistance_.push_back(resistance[k]);
      }
    }
  }
}

template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::scatter_momentum(const std::vector<Vec<Dim>>& v_p) {
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()),
               [&](std::ptrdiff_t n) { grid_.nodes[n].v_new.setZero(); });
  if (affine())
    p2g_add(stencils(), order_, grid_,
            AffineMomentum<Dim, NodeSlots<Dim>::v_new, false>{particles_.m, v_p, *affine()});
  else
    p2g_add(stencils(), order_, grid_, Momentum<Dim, NodeSlots<Dim>::v_new, false>{particles_.m, v_p});
  periodic_halo_.sum_into_owners(grid_, &GridNode<Dim>::v_new);
  constraints_.fold_and_mirror(grid_, &GridNode<Dim>::v_new);
}

// Internal force f_i = -sum_p V_p sigma_p grad N_i(x_p^k) (Sulsky & Kaul 2004, Eq. (2.2.9), Eq. (2.2.10),
// Eq. (2.4.7)), with the hoop term -V_p sigma_thetatheta N_i / r_p on the radial component in axisymmetry
// (Sulsky & Schreyer 1996).
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::scatter_force(const std::vector<SymTensor<3>>& sigma,
                                                    std::vector<Vec<Dim>>& f) {
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()),
               [&](std::ptrdiff_t n) { grid_.nodes[n].a.setZero(); });
  const ParticleSet<Dim>& p = particles_;
  p2g_add(stencils(), order_, grid_, InternalForce<Dim, SymTensor<3>>{p.V, sigma});
  if constexpr (Dim == 2)  // the hoop force in a pass of its own, as in the explicit step
    if (spec_.geometry == Geometry::axisymmetric)
      p2g_add(stencils(), order_, grid_, HoopForce{p.V, sigma, p.x});
  periodic_halo_.sum_into_owners(grid_, NodeFields::force);
  constraints_.fold_and_mirror(grid_, NodeFields::force);
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) { f[n] = grid_.nodes[n].a; });
}

// The body force's and the surface loads' share of the external force, f_i += sum_p S_ip m_p b_p, with b_p =
// (1 - theta) b(X_p, t^k) + theta b(X_p, t^{k+1}) blended as the internal forces are (Sulsky & Kaul 2004,
// Eq. (2.4.1)), and the surface loads' moments blended alike (BodyForce); a pressure's direction is that of
// the step's start, where the stencils are.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::add_body_force(Real dt) {
  const ParticleSet<Dim>& p = particles_;
  const Real theta = spec_.theta, t0 = time_, t1 = time_ + dt;
  body_accel_.clear();
  if (spec_.body_force) {
    body_accel_.resize(p.size());
    parallel_for(static_cast<std::ptrdiff_t>(p.size()), [&](std::ptrdiff_t i) {
      body_accel_[i] = (1 - theta) * spec_.body_force(p.X[i], t0) + theta * spec_.body_force(p.X[i], t1);
    });
  }
  if (!spec_.surface_loads.empty()) {
    surface_.reset(p);
    spec_.surface_loads.add_to_particles(p, t0, 1 - theta, spec_.geometry, surface_);
    spec_.surface_loads.add_to_particles(p, t1, theta, spec_.geometry, surface_);
    surface_.start(p);
  }
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()),
               [&](std::ptrdiff_t n) { grid_.nodes[n].a.setZero(); });
  p2g_add(stencils(), order_, grid_,
          BodyForce<Dim>{p.m, spec_.body_force ? &body_accel_ : nullptr,
                         spec_.surface_loads.empty() ? nullptr : &surface_, &p.F});
  periodic_halo_.sum_into_owners(grid_, NodeFields::force);
  constraints_.fold_and_mirror(grid_, NodeFields::force);
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()),
               [&](std::ptrdiff_t n) { f_ext_[n] += grid_.nodes[n].a; });
}

template <int Dim, class Kernel>
template <class Value>
void ImplicitSimulation<Dim, Kernel>::gather_over_active_nodes(Value value, std::vector<Vec<Dim>>& out) {
  put_on_active_nodes(value);
  g2p_interpolate(stencils(), grid_, &GridNode<Dim>::a, out);
}

template <int Dim, class Kernel>
template <class Value>
void ImplicitSimulation<Dim, Kernel>::put_on_active_nodes(Value value) {
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid_.nodes[n];
    node.a = node.m > min_node_mass_ ? Vec<Dim>(value(node, static_cast<std::size_t>(n))) : Vec<Dim>::Zero();
  });
}

}  // namespace mpm

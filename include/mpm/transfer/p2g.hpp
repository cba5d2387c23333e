#pragma once
/// Particle-to-grid transfers: mass, momentum and force scattered through the precomputed stencils.
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

/// What a P2G pass scatters.
struct Scatter {
  bool mass_momentum;
  bool force;
};

/// Scatter particle data to the grid. Mass and momentum: Wallstedt & Guilkey 2008, Eqs (8)-(9) (the
/// division by m_i happens in grid_velocity). Force: internal force Eq. (14), f_i = -sum_p grad S_ip .
/// sigma_p V_p, plus the body force sum_p S_ip m_p b_p when per-particle body accelerations b are given.
template <Scatter what, int Dim, class Kernel>
void p2g(const ParticleSet<Dim>& p, const std::vector<Stencil<Dim, Kernel>>& stencils,
         const ScatterOrder& order, const std::vector<Vec<Dim>>& body_accel, Grid<Dim>& grid) {
  const NodeLayout<Dim> layout(grid.geometry);
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid.nodes[n];
    if constexpr (what.mass_momentum) {
      node.m = 0;
      node.v.setZero();
    }
    if constexpr (what.force) node.a.setZero();
  });
  // The body-force term is compiled in only when there is one.
  auto scatter = [&]<bool body>() {
    order.for_each([&](std::int32_t i) {
      const Real m_p = p.m[i];
      const Vec<Dim> mv_p = m_p * p.v[i];
      const Mat<Dim> Vsigma_p = p.V[i] * p.sigma[i].full();
      for_each_node(stencils[i], layout, [&](std::int32_t n, Real S_ip, const Vec<Dim>& dS_ip) {
        GridNode<Dim>& node = grid.nodes[n];
        if constexpr (what.mass_momentum) {
          node.m += S_ip * m_p;
          node.v += S_ip * mv_p;
        }
        if constexpr (what.force) {
          node.a -= Vsigma_p * dS_ip;
          if constexpr (body) node.a += (S_ip * m_p) * body_accel[i];
        }
      });
    });
  };
  if (what.force && !body_accel.empty())
    scatter.template operator()<true>();
  else
    scatter.template operator()<false>();
}

/// Turn nodal momentum into velocity v_i = p_i / m_i (Wallstedt & Guilkey 2008, Eq. 9); empty nodes get zero.
template <int Dim>
void grid_velocity(Grid<Dim>& grid, Real min_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid.nodes[n];
    if (node.m > min_mass)
      node.v /= node.m;
    else
      node.v.setZero();
  });
}

/// Turn nodal force into acceleration a_i = (f_int + f_ext)/m_i + g (Eq. 15) scaled by `scale`, and advance
/// the velocity v_i^* = v_i + a_i dt (Eq. 16).
template <int Dim>
void grid_update(Grid<Dim>& grid, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid.nodes[n];
    if (node.m > min_mass)
      node.a = scale * (node.a / node.m + gravity);
    else
      node.a.setZero();
    node.v_new = node.v + dt * node.a;
  });
}

}  // namespace mpm

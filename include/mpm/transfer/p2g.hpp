#pragma once
/// Particle-to-grid transfers: mass, momentum and force scattered through the precomputed stencils.
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/lanes.hpp"
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
    if constexpr (what.mass_momentum && what.force) {  // v_new is recomputed from these, so clear all at once
      std::memset(static_cast<void*>(&node), 0, sizeof(node));
      return;
    }
    if constexpr (what.mass_momentum) {
      node.m = 0;
      node.v.setZero();
    }
    if constexpr (what.force) node.a.setZero();
  });
  // Particles go in scatter order, `lanes` at a time: their contributions to the nodes of their stencils are
  // computed in lanes and added to the node records particle by particle, so each node receives
  // them in the same order as one particle at a time. The body-force term is compiled in only when there is
  // one.
  constexpr int R = reals_in<GridNode<Dim>>;
  constexpr std::size_t stencil_nodes = LaneStencil<Dim, Kernel>::node_count;
  static_assert(sizeof(GridNode<Dim>) == R * sizeof(Real), "a node is a record of Reals");
  const GridNode<Dim>& node0 = grid.nodes[0];
  const int v_slot = static_cast<int>(&node0.v[0] - &node0.m), a_slot = static_cast<int>(&node0.a[0] - &node0.m);
  Real* nodes = &grid.nodes[0].m;
  auto scatter = [&]<bool body>() {
    order.template for_each_block<LaneBlock::width>([&](const std::int32_t* particles, int count) {
      const LaneBlock block(particles, count);
      const LaneStencil<Dim, Kernel> s(stencils, block, layout.inv_h);
      const RealLanes m_p = block.load(p.m)[0];
      RealLanes mv_p[Dim], Vsigma_p[Dim][Dim], b_p[Dim];
      if constexpr (what.mass_momentum) {
        const RecordLanes<Vec<Dim>> v = block.load(p.v);
        for (int d = 0; d < Dim; ++d) mv_p[d] = m_p * v[d];
      }
      if constexpr (what.force) {
        const RealLanes V_p = block.load(p.V)[0];
        const RecordLanes<SymTensor<Dim>> sigma = block.load(p.sigma);
        for (int a = 0; a < Dim; ++a)
          for (int c = 0; c < Dim; ++c) Vsigma_p[a][c] = V_p * sigma[SymTensor<Dim>::index(a, c)];
        if constexpr (body) {
          const RecordLanes<Vec<Dim>> b = block.load(body_accel);
          for (int d = 0; d < Dim; ++d) b_p[d] = b[d];
        }
      }
      std::array<std::array<RealLanes, R>, stencil_nodes> records;
      std::array<std::int32_t, stencil_nodes> offsets;
      int o = 0;
      for_each_node(s, layout, [&](std::int32_t offset, const RealLanes& S_ip, const RealLanes(&dS_ip)[Dim]) {
        std::array<RealLanes, R>& record = records[o];
        record = {};  // the slots this pass does not scatter add zero
        offsets[o++] = offset;
        if constexpr (what.mass_momentum) {
          record[0] = S_ip * m_p;
          for (int d = 0; d < Dim; ++d) record[v_slot + d] = S_ip * mv_p[d];
        }
        if constexpr (what.force)
          for (int d = 0; d < Dim; ++d) {
            RealLanes f = Vsigma_p[d][0] * dS_ip[0];
            for (int c = 1; c < Dim; ++c) f += Vsigma_p[d][c] * dS_ip[c];
            record[a_slot + d] = body ? (S_ip * m_p) * b_p[d] - f : -f;
          }
      });
      simd::add_stencil_records<R>(nodes, s.node, offsets, records, block.active);
    });
  };
  if (what.force && !body_accel.empty())
    scatter.template operator()<true>();
  else
    scatter.template operator()<false>();
}

/// Turn nodal momentum into velocity v_i = p_i / m_i (Wallstedt & Guilkey 2008, Eq. 9); empty nodes get zero.
template <int Dim>
inline void node_velocity(GridNode<Dim>& node, Real min_mass) {
  if (node.m > min_mass)
    node.v /= node.m;
  else
    node.v.setZero();
}

/// Turn nodal force into acceleration a_i = (f_int + f_ext)/m_i + g (Eq. 15) scaled by `scale`, and advance
/// the velocity v_i^* = v_i + a_i dt (Eq. 16).
template <int Dim>
inline void node_update(GridNode<Dim>& node, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass) {
  if (node.m > min_mass)
    node.a = scale * (node.a / node.m + gravity);
  else
    node.a.setZero();
  node.v_new = node.v + dt * node.a;
}

/// node_velocity at every node.
template <int Dim>
void grid_velocity(Grid<Dim>& grid, Real min_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) { node_velocity(grid.nodes[n], min_mass); });
}

/// node_update at every node.
template <int Dim>
void grid_update(Grid<Dim>& grid, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()),
               [&](std::ptrdiff_t n) { node_update(grid.nodes[n], gravity, dt, scale, min_mass); });
}

/// grid_velocity then grid_update, in one pass over the nodes.
template <int Dim>
void grid_velocity_update(Grid<Dim>& grid, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) {
    node_velocity(grid.nodes[n], min_mass);
    node_update(grid.nodes[n], gravity, dt, scale, min_mass);
  });
}

/// The mass below which a node is light: a fixed mass, or in axisymmetry, where masses are per radian and grow
/// with the radius, a mass per unit radius times the node's radius |r_i|.
template <int Dim>
struct LightMass {
  Real mass = 0;        ///< [kg]; 0: no node is light
  Real per_radius = 0;  ///< [kg/m per radian]; > 0 in axisymmetry, which then ignores `mass`
  Real lo = 0, h = 1;   ///< the grid's radial origin and cell width [m]
  int nodes_along = 1, ghost = 0;

  bool any() const { return mass > 0 || per_radius > 0; }
  Real operator()(std::ptrdiff_t n) const {
    if (per_radius == 0) return mass;
    return per_radius * std::abs(lo + h * static_cast<Real>(n % nodes_along - ghost));
  }
};

/// A node that carries mass, but less than `light_mass` once its mirror images are counted (`copies`, see
/// KinematicConstraints::count_mirror_copies).
template <int Dim>
inline bool light(const GridNode<Dim>& node, std::uint8_t copies, Real min_mass, Real light_mass) {
  return node.m > min_mass && node.m * copies < light_mass;
}

/// Whether any node is light.
template <int Dim>
bool any_light(const Grid<Dim>& grid, const std::vector<std::uint8_t>& copies, Real min_mass,
               const LightMass<Dim>& light_mass) {
  bool found = false;
#pragma omp parallel for schedule(static) reduction(|| : found)
  for (std::ptrdiff_t n = 0; n < static_cast<std::ptrdiff_t>(grid.size()); ++n)
    found = found || light(grid.nodes[n], copies[n], min_mass, light_mass(n));
  return found;
}

/// On light nodes, the velocity that moves the particles and deforms them becomes the re-projected one:
/// v_new = v, with v the updated particle momenta over the node's mass (Sulsky & Kaul 2004, Eq. (3.2.7);
/// Wallstedt & Guilkey 2008, Eq. (51) at these nodes only). A mass-weighted mean of particle velocities, it
/// stays bounded however small m_i is.
template <int Dim>
void reprojected_on_light_nodes(Grid<Dim>& grid, const std::vector<std::uint8_t>& copies, Real min_mass,
                                const LightMass<Dim>& light_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) {
    GridNode<Dim>& node = grid.nodes[n];
    if (light(node, copies[n], min_mass, light_mass(n))) node.v_new = node.v;
  });
}

}  // namespace mpm

#pragma once
/// Particle-to-grid transfers: mass, momentum and force scattered through the precomputed stencils.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <tuple>
#include <vector>

#include "mpm/boundary/surface_loads.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/lanes.hpp"
#include "mpm/transfer/passes.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

/// What particles add to the node records in a P2G pass. Each contribution, called with a block of particles,
/// loads their data in lanes and returns the function that adds their share at one stencil node,
/// add(record, S_ip, grad S_ip): a node's record gets the contributions of one pass in the order listed.

/// Mass m_p S_ip and momentum m_p v_p S_ip into the node field at `slot` (Wallstedt & Guilkey 2008, Eq. (8),
/// Eq. (9): the division by m_i happens in grid_velocity), or the momentum alone when `with_mass` is false
/// (the re-projection of Sulsky & Kaul 2004, Eq. (3.2.7)).
template <int Dim, int slot = NodeSlots<Dim>::v, bool with_mass = true>
struct Momentum {
  static constexpr int slots_end = slot + Dim;  ///< one past the last record slot it adds to
  const std::vector<Real>& m;
  const std::vector<Vec<Dim>>& v;

  [[gnu::always_inline]] auto operator()(const LaneBlock& block) const {
    const RealLanes m_p = block.load(m)[0];
    const RecordLanes<Vec<Dim>> v_p = block.load(v);
    std::array<RealLanes, Dim> mv_p;
    for (int d = 0; d < Dim; ++d) mv_p[d] = m_p * v_p[d];
    return [ m_p, mv_p ](auto& record, const RealLanes& S_ip, const RealLanes(&)[Dim])
        __attribute__((always_inline)) {
      if constexpr (with_mass) record[NodeSlots<Dim>::m] += S_ip * m_p;
      for (int d = 0; d < Dim; ++d) record[slot + d] += S_ip * mv_p[d];
    };
  }
};

/// APIC's mass and momentum (Jiang et al. 2015): m_p S_ip and m_p S_ip (v_p + B_p D_p^-1 (x_i - x_p)) into
/// the node field at `slot`, B_p the particle's affine matrix (g2p_affine) and D_p its inertia tensor at its
/// current position (LaneStencil::locate_nodes). It carries the particle's angular momentum m_p (x_p x v_p +
/// eps : B_p^T) to the grid; with B_p = 0 it is Momentum.
template <int Dim, int slot = NodeSlots<Dim>::v, bool with_mass = true>
struct AffineMomentum {
  static constexpr bool affine = true;  ///< its add takes S_ip D_p^-1 (x_i - x_p) (NodeMoment::affine)
  static constexpr int slots_end = slot + Dim;
  const std::vector<Real>& m;
  const std::vector<Vec<Dim>>& v;
  const std::vector<Mat<Dim>>& B;

  [[gnu::always_inline]] auto operator()(const LaneBlock& block) const {
    const RealLanes m_p = block.load(m)[0];
    const RecordLanes<Vec<Dim>> v_p = block.load(v);
    const RecordLanes<Mat<Dim>> B_p = block.load(B);  // column-major: B(c, d) is Real c + d Dim
    std::array<RealLanes, Dim> mv_p;
    std::array<std::array<RealLanes, Dim>, Dim> mB_p;
    for (int c = 0; c < Dim; ++c) {
      mv_p[c] = m_p * v_p[c];
      for (int d = 0; d < Dim; ++d) mB_p[c][d] = m_p * B_p[c + d * Dim];
    }
    return [ m_p, mv_p, mB_p ](auto& record, const RealLanes& S_ip, const RealLanes(&)[Dim],
                               const RealLanes(&Sq_ip)[Dim]) __attribute__((always_inline)) {
      if constexpr (with_mass) record[NodeSlots<Dim>::m] += S_ip * m_p;
      for (int c = 0; c < Dim; ++c) {
        RealLanes p = S_ip * mv_p[c];
        for (int d = 0; d < Dim; ++d) p += mB_p[c][d] * Sq_ip[d];
        record[slot + c] += p;
      }
    };
  }
};

/// Whether a P2G contribution's add takes APIC's moment S_ip D_p^-1 (x_i - x_p).
template <class Contribution>
inline constexpr bool takes_affine_moment = requires {
  Contribution::affine;
};

/// Internal force f_i = -sum_p grad S_ip . sigma_p V_p (Wallstedt & Guilkey 2008, Eq. (14); Sulsky & Kaul
/// 2004, Eq. (2.2.10)) into the force slot. `Stress` is SymTensor<Dim>, or SymTensor<3> of which the in-plane
/// part acts; when `state` is set, its 3 x 3 stresses (a rate-form material state's) are read instead of
/// `sigma`.
template <int Dim, class Stress>
struct InternalForce {
  static constexpr int slots_end = NodeSlots<Dim>::a + Dim;
  const std::vector<Real>& V;
  const std::vector<Stress>& sigma;
  const std::vector<SymTensor<3>>* state = nullptr;

  [[gnu::always_inline]] auto operator()(const LaneBlock& block) const {
    const RealLanes V_p = block.load(V)[0];
    std::array<std::array<RealLanes, Dim>, Dim> Vsigma_p;
    const auto scale = [&](const auto& sigma_p, auto index) __attribute__((always_inline)) {
      for (int a = 0; a < Dim; ++a)
        for (int c = 0; c < Dim; ++c) Vsigma_p[a][c] = V_p * sigma_p[index(a, c)];
    };
    if (state)
      scale(block.load(*state), SymTensor<3>::index);
    else
      scale(block.load(sigma), Stress::index);
    return [Vsigma_p](auto& record, const RealLanes&, const RealLanes(&dS_ip)[Dim])
        __attribute__((always_inline)) {
      for (int d = 0; d < Dim; ++d) {
        RealLanes f_d = Vsigma_p[d][0] * dS_ip[0];
        for (int c = 1; c < Dim; ++c) f_d += Vsigma_p[d][c] * dS_ip[c];
        record[NodeSlots<Dim>::a + d] -= f_d;
      }
    };
  }
};

/// Body force sum_p S_ip m_p b_p, b_p a per-particle acceleration, into the force slot (part of the external
/// force of Wallstedt & Guilkey 2008, Eq. (15)); with `surface`, also the surface loads the particles carry,
/// sum_p S_ip f_p + grad S_ip . (A_p F_p^T) with F the particles' deformation gradients: each face's force
/// acting at its face rather than at the particle's centre (patch_load).
template <int Dim>
struct BodyForce {
  static constexpr int slots_end = NodeSlots<Dim>::a + Dim;
  const std::vector<Real>& m;
  const std::vector<Vec<Dim>>* b = nullptr;
  const SurfaceLoading<Dim>* surface = nullptr;
  const std::vector<Mat<Dim>>* F = nullptr;

  [[gnu::always_inline]] auto operator()(const LaneBlock& block) const {
    const RealLanes m_p = block.load(m)[0];
    const bool body = b != nullptr, loaded = surface != nullptr;
    RecordLanes<Vec<Dim>> b_p{}, f_p{};
    std::array<std::array<RealLanes, Dim>, Dim> M_p{};  // A_p F_p^T
    if (body) b_p = block.load(*b);
    if (loaded) {
      f_p = block.load(surface->force);
      const RecordLanes<Mat<Dim>> A_p = block.load(surface->moment), F_p = block.load(*F);  // column-major
      for (int d = 0; d < Dim; ++d)
        for (int c = 0; c < Dim; ++c) {
          RealLanes sum = A_p[d] * F_p[c];
          for (int e = 1; e < Dim; ++e) sum += A_p[d + e * Dim] * F_p[c + e * Dim];
          M_p[d][c] = sum;
        }
    }
    return [ m_p, b_p, f_p, M_p, body, loaded ](auto& record, const RealLanes& S_ip,
                                                const RealLanes(&dS_ip)[Dim]) __attribute__((always_inline)) {
      for (int d = 0; d < Dim; ++d) {
        if (body) record[NodeSlots<Dim>::a + d] += (S_ip * m_p) * b_p[d];
        if (loaded) {
          RealLanes f_d = S_ip * f_p[d];
          for (int c = 0; c < Dim; ++c) f_d += M_p[d][c] * dS_ip[c];
          record[NodeSlots<Dim>::a + d] += f_d;
        }
      }
    };
  }
};

/// The hoop term of the internal force in axisymmetry, -V_p sigma_thetatheta S_ip / r_p on the radial
/// component (Sulsky & Schreyer 1996), r_p the particle's radius.
struct HoopForce {
  static constexpr int slots_end = NodeSlots<2>::a + 1;
  const std::vector<Real>& V;
  const std::vector<SymTensor<3>>& sigma;
  const std::vector<Vec<2>>& x;

  [[gnu::always_inline]] auto operator()(const LaneBlock& block) const {
    const RealLanes hoop = block.load(V)[0] * block.load(sigma)[2] / block.load(x)[0];
    return [hoop](auto& record, const RealLanes& S_ip, const RealLanes(&)[2]) __attribute__((always_inline)) {
      record[NodeSlots<2>::a] -= hoop * S_ip;
    };
  }
};

/// The volume gradient sum_p V_p grad S_ip of a body's particles into the v_new slot, which a pass that
/// scatters mass leaves free: it points out of the body at its surface nodes, and contact takes its normals
/// from it (Bardenhagen, Brackbill & Sulsky 2000; Nairn 2013 on volume rather than mass gradients).
template <int Dim>
struct VolumeGradient {
  static constexpr int slots_end = NodeSlots<Dim>::v_new + Dim;
  const std::vector<Real>& V;

  [[gnu::always_inline]] auto operator()(const LaneBlock& block) const {
    const RealLanes V_p = block.load(V)[0];
    return [V_p](auto& record, const RealLanes&, const RealLanes(&dS_ip)[Dim])
        __attribute__((always_inline)) {
      for (int d = 0; d < Dim; ++d) record[NodeSlots<Dim>::v_new + d] += V_p * dS_ip[d];
    };
  }
};

/// P2G: the contributions of every particle added to the records of the nodes of its stencil, in
/// ScatterOrder. Particles go `lanes` at a time: their contributions are computed in lanes and added to their
/// tile's footprint buffer particle by particle, so each tile's sum receives them in the same order as one
/// particle at a time, whatever the thread count. The fields the contributions add to are not cleared first.
/// Each tile's sums are shown to keep(tile, footprint records) before they are added into the grid (the halo
/// keeps those of the tiles at a box's faces). Only the particles of velocity field `field` contribute
/// (ScatterOrder::build).
template <int Dim, class Kernel, class Keep, class... Contributions>
void p2g_add_keeping(const Keep& keep, const ParticleStencils<Dim, Kernel>& stencils,
                     const ScatterOrder<Dim>& order, int field, Grid<Dim>& grid,
                     const Contributions&... contributions) {
  constexpr int R = reals_in<GridNode<Dim>>;
  using Lanes = LaneStencil<Dim, Kernel>;
  constexpr std::size_t stencil_nodes = Lanes::node_count;
  static_assert(sizeof(GridNode<Dim>) == R * sizeof(Real), "a node is a record of Reals");
  // The footprint buffer's strides: Lanes::footprint records per axis.
  NodeLayout<Dim> layout(grid.geometry);
  for (int d = 0, stride = 1; d < Dim; ++d, stride *= Lanes::footprint) layout.stride[d] = stride;
  constexpr bool affine = (takes_affine_moment<Contributions> || ...);
  // The leading slots of a record the contributions add to, rounded up to a register's width where a record
  // holds that many (add_stencil_records then adds a node's share with one vector add): slots past them are
  // left alone.
  constexpr int written = std::max({Contributions::slots_end...});
  constexpr int W = written <= simd::lanes && simd::lanes <= R ? simd::lanes : written;
  order.template scatter<LaneBlock::width>(
      grid,
      [&](Real* buffer, const std::int32_t* particles, int count) {
        const LaneBlock block(particles, count);
        Lanes s(stencils, block, grid.geometry, layout.inv_h);
        if constexpr (affine) s.locate_nodes(grid.geometry.h);
        const auto add = std::make_tuple(contributions(block)...);
        std::array<std::array<RealLanes, W>, stencil_nodes> records;
        std::array<std::int32_t, stencil_nodes> offsets;
        int o = 0;
        for_each_node<affine ? NodeMoment::affine : NodeMoment::none>(
            s, layout,
            [&](std::int32_t offset, const RealLanes& S_ip, const RealLanes(&dS_ip)[Dim],
                const auto&... Sq_ip) __attribute__((always_inline)) {
              std::array<RealLanes, W>& record = records[o];
              record = {};  // the slots no contribution adds to add zero
              offsets[o++] = offset;
              const auto add_to = [&](const auto& add_one) __attribute__((always_inline)) {
                if constexpr (requires { add_one(record, S_ip, dS_ip, Sq_ip...); })
                  add_one(record, S_ip, dS_ip, Sq_ip...);
                else
                  add_one(record, S_ip, dS_ip);
              };
              std::apply(
                  [&](const auto&... add_one) __attribute__((always_inline)) { (add_to(add_one), ...); },
                  add);
            });
        simd::add_stencil_records<R>(buffer, s.slot, offsets, records, block.active);
      },
      keep, field);
}

/// The `keep` of a pass that does not look at the tiles' sums (one process).
struct KeepNothing {
  template <int Dim>
  void operator()(std::int32_t, const GridNode<Dim>*) const {}
};

/// p2g_add_keeping of every particle (one velocity field) without a look at the tiles' sums.
template <int Dim, class Kernel, class... Contributions>
void p2g_add(const ParticleStencils<Dim, Kernel>& stencils, const ScatterOrder<Dim>& order, Grid<Dim>& grid,
             const Contributions&... contributions) {
  p2g_add_keeping(KeepNothing{}, stencils, order, 0, grid, contributions...);
}

/// The explicit step's P2G of velocity field `field`'s particles: clear the fields it scatters, then add mass
/// and momentum (Wallstedt & Guilkey 2008, Eq. (8), Eq. (9)) with, for contact, the volume gradient, and the
/// internal force plus, when per-particle body accelerations are given, the body force (Wallstedt & Guilkey
/// 2008, Eq. (14), Eq. (15)). Each tile's sums are shown to keep (p2g_add_keeping). The stress is p.sigma, or
/// with `state_stress` the 3 x 3 stress of the material state (the engine's when it keeps one). With
/// `affine`, the particles' APIC matrices B_p, the momentum is APIC's (AffineMomentum). With `surface`, the
/// surface loads the particles carry, the body force adds them (BodyForce).
template <Scatter what, int Dim, class Kernel, class Keep = KeepNothing>
void p2g(const ParticleSet<Dim>& p, const ParticleStencils<Dim, Kernel>& stencils,
         const ScatterOrder<Dim>& order, const std::vector<Vec<Dim>>& body_accel, Grid<Dim>& grid,
         const Keep& keep = {}, int field = 0, bool state_stress = false,
         const std::vector<Mat<Dim>>* affine = nullptr, const SurfaceLoading<Dim>* surface = nullptr) {
  static_assert(!what.volume_gradient || what.mass_momentum, "the volume gradient comes with the mass");
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
    if constexpr (what.volume_gradient) node.v_new.setZero();
    if constexpr (what.force) node.a.setZero();
  });
  const InternalForce<Dim, SymTensor<Dim>> internal{p.V, p.sigma, state_stress ? &p.state.sigma : nullptr};
  const bool body = what.force && (!body_accel.empty() || surface);
  const BodyForce<Dim> body_force{p.m, body_accel.empty() ? nullptr : &body_accel, surface, &p.F};
  const auto add = [&](const auto&... contributions) {
    p2g_add_keeping(keep, stencils, order, field, grid, contributions...);
  };
  const auto with_gradient = [&](const auto&... contributions) {
    if constexpr (what.volume_gradient)
      add(contributions..., VolumeGradient<Dim>{p.V});
    else
      add(contributions...);
  };
  const auto with_momentum = [&](const auto&... contributions) {
    if (affine)
      with_gradient(AffineMomentum<Dim>{p.m, p.v, *affine}, contributions...);
    else
      with_gradient(Momentum<Dim>{p.m, p.v}, contributions...);
  };
  if constexpr (what.mass_momentum && what.force) {
    if (body)
      with_momentum(internal, body_force);
    else
      with_momentum(internal);
  } else if constexpr (what.mass_momentum) {
    with_momentum();
  } else if (body) {
    add(internal, body_force);
  } else {
    add(internal);
  }
}

/// Turn a nodal momentum into velocity v_i = p_i / m_i (Wallstedt & Guilkey 2008, Eq. (9)) in place; a node
/// of mass min_mass or less gets zero. Both engines' projections of momentum end here.
template <int Dim>
inline void momentum_to_velocity(Vec<Dim>& momentum, Real m, Real min_mass) {
  if (m > min_mass)
    momentum /= m;
  else
    momentum.setZero();
}
/// momentum_to_velocity of the node's momentum v.
template <int Dim>
inline void node_velocity(GridNode<Dim>& node, Real min_mass) {
  momentum_to_velocity(node.v, node.m, min_mass);
}

/// Turn nodal force into acceleration a_i = (f_int + f_ext)/m_i + g (Wallstedt & Guilkey 2008,
/// Eq. (15)) scaled by `scale`, and advance the velocity v_i^* = v_i + a_i dt (Wallstedt & Guilkey 2008,
/// Eq. (16)). With local damping alpha > 0 each component of the unbalanced force is reduced by alpha times
/// its size against the node's velocity, a_c -= alpha |a_c| sign(v_c) (Cundall 1987, non-viscous damping).
template <int Dim>
inline void node_update(GridNode<Dim>& node, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass,
                        Real damping) {
  if (node.m > min_mass) {
    node.a = scale * (node.a / node.m + gravity);
    if (damping > 0)
      for (int c = 0; c < Dim; ++c)
        node.a[c] -= damping * std::abs(node.a[c]) * static_cast<Real>((node.v[c] > 0) - (node.v[c] < 0));
  } else {
    node.a.setZero();
  }
  node.v_new = node.v + dt * node.a;
}

/// node_velocity at every node.
template <int Dim>
void grid_velocity(Grid<Dim>& grid, Real min_mass) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()),
               [&](std::ptrdiff_t n) { node_velocity(grid.nodes[n], min_mass); });
}

/// node_update at every node.
template <int Dim>
void grid_update(Grid<Dim>& grid, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass, Real damping) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()),
               [&](std::ptrdiff_t n) { node_update(grid.nodes[n], gravity, dt, scale, min_mass, damping); });
}

/// grid_velocity then grid_update, in one pass over the nodes.
template <int Dim>
void grid_velocity_update(Grid<Dim>& grid, const Vec<Dim>& gravity, Real dt, Real scale, Real min_mass,
                          Real damping) {
  parallel_for(static_cast<std::ptrdiff_t>(grid.size()), [&](std::ptrdiff_t n) {
    node_velocity(grid.nodes[n], min_mass);
    node_update(grid.nodes[n], gravity, dt, scale, min_mass, damping);
  });
}

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
  return parallel_reduce(
      static_cast<std::ptrdiff_t>(grid.size()), false,
      [&](std::ptrdiff_t n) { return light(grid.nodes[n], copies[n], min_mass, light_mass(n)); },
      [](bool a, bool b) { return a || b; });
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

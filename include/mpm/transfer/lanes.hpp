#pragma once
/// Stencils and grid values of a LaneBlock of particles in SIMD lanes, for the transfers.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mpm/core/simd.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/lanes.hpp"
#include "mpm/shape/stencil.hpp"

namespace mpm {

/// The base nodes of a block's stencils in lanes, and the gather of node values through them.
template <int Dim, class Kernel>
struct LaneNodes {
  static constexpr int N = Kernel::width;
  static constexpr std::size_t node_count = Dim == 1   ? N
                                            : Dim == 2 ? N * N
                                                       : N * N * N;  ///< nodes per stencil
  /// Node layers per axis of a tile's footprint: its own and those its particles' stencils reach above it.
  static constexpr int footprint = GridGeometry<Dim>::tile_width + N - 1;
  IntLanes node;  ///< flat index of each lane's base node
  IntLanes slot;  ///< flat index of each lane's base node in its tile's footprint (axis 0 fastest)

  [[gnu::always_inline]] explicit LaneNodes(const StencilLanes<Dim, Kernel>& s) : node(s.node), slot{} {
    using G = GridGeometry<Dim>;
    for (int d = Dim - 1; d >= 0; --d)
      slot = slot * footprint + ((s.tile_slot >> (G::tile_shift * d)) & (G::tile_width - 1));
  }

  /// Lanes of get(node) at node (base + offset) of every lane.
  template <class Get>
  [[gnu::always_inline]] RealLanes gather(const std::vector<GridNode<Dim>>& nodes, std::int32_t offset,
                                          Get&& get) const {
    static_assert(sizeof(GridNode<Dim>) % sizeof(Real) == 0);
    return simd::gather(&get(nodes[0]), (node + offset) * reals_in<GridNode<Dim>>);
  }
};

/// The stencils of a block in lanes: base nodes, and per axis the weights and gradients [1/m] of each node.
template <int Dim, class Kernel>
struct LaneStencil : LaneNodes<Dim, Kernel> {
  static constexpr int N = Kernel::width;
  RealLanes w[Dim][N], dw[Dim][N];
  /// Set by locate_nodes (APIC only): dx[d][k] = x_i - x_p along axis d for the k-th node of the axis [m],
  /// and the inverse of the diagonal of the particle's inertia tensor D_p (0 where a diagonal entry is 0).
  RealLanes dx[Dim][N], inv_D[Dim];

  [[gnu::always_inline]] LaneStencil(const ParticleStencils<Dim, Kernel>& stencils, const LaneBlock& block,
                                     const GridGeometry<Dim>& g, Real inv_h)
      : LaneStencil(stencils.lanes(block, g, inv_h), inv_h) {}
  [[gnu::always_inline]] LaneStencil(const StencilLanes<Dim, Kernel>& s, Real inv_h)
      : LaneNodes<Dim, Kernel>(s) {
    for (int d = 0; d < Dim; ++d) {
      Kernel::weights_at(s.axis[d], w[d], dw[d]);
      for (int a = 0; a < N; ++a) dw[d][a] *= inv_h;
    }
  }

  /// The nodes' offsets from the particles and the particles' inertia tensors of APIC, D_p = sum_i S_ip
  /// (x_i - x_p)(x_i - x_p)^T (Jiang et al. 2015). A kernel that reproduces linear fields puts the particle
  /// at sum_k k w_k cells from its base node, so dx follows from the weights alone; the first moments sum_k
  /// w_k dx_k then vanish, and D_p of a tensor product is diagonal, D_dd = sum_k w_dk dx_dk^2.
  [[gnu::always_inline]] void locate_nodes(Real h) {
    for (int d = 0; d < Dim; ++d) {
      RealLanes offset = w[d][1];
      for (int k = 2; k < N; ++k) offset += k * w[d][k];
      RealLanes D{};
      for (int k = 0; k < N; ++k) {
        dx[d][k] = (k - offset) * h;
        D += w[d][k] * dx[d][k] * dx[d][k];
      }
      inv_D[d] = D > 0 ? 1 / D : RealLanes{};  // D = 0: every S_ip dx is 0 (a hat's particle on its node)
    }
  }
};

/// What for_each_node hands over besides the weights and their gradients (LaneStencil::locate_nodes first).
enum class NodeMoment {
  none,    ///< fn(offset, S_ip, grad S_ip)
  offset,  ///< fn(offset, S_ip, grad S_ip, S_ip (x_i - x_p))
  affine,  ///< fn(offset, S_ip, grad S_ip, S_ip D_p^-1 (x_i - x_p)), APIC's P2G weight
};

/// Visit every node of the tensor-product stencils of a block: fn(offset of the node from each lane's base
/// node, weights S_ip, gradients grad S_ip [1/m] by axis, and the `moment` asked for). The same products as
/// for_each_node, in lanes.
template <NodeMoment moment = NodeMoment::none, int Dim, class Kernel, class Fn>
[[gnu::always_inline]] inline void for_each_node(const LaneStencil<Dim, Kernel>& s, const NodeLayout<Dim>& nl,
                                                 Fn&& fn) {
  constexpr int N = Kernel::width;
  // fn with the moment of the node whose index along each axis is k.
  const auto visit = [&](std::int32_t offset, const RealLanes& S, const RealLanes(&dS)[Dim],
                         const int(&k)[Dim]) __attribute__((always_inline)) {
    if constexpr (moment == NodeMoment::none) {
      fn(offset, S, dS);
    } else {
      RealLanes Sx[Dim];
      for (int d = 0; d < Dim; ++d) {
        Sx[d] = S * s.dx[d][k[d]];
        if constexpr (moment == NodeMoment::affine) Sx[d] *= s.inv_D[d];
      }
      fn(offset, S, dS, Sx);
    }
  };
  if constexpr (Dim == 1) {
    for (int a = 0; a < N; ++a) {
      const RealLanes dS[1] = {s.dw[0][a]};
      visit(a, s.w[0][a], dS, {a});
    }
  } else if constexpr (Dim == 2) {
    for (int b = 0; b < N; ++b)
      for (int a = 0; a < N; ++a) {
        const RealLanes dS[2] = {s.dw[0][a] * s.w[1][b], s.w[0][a] * s.dw[1][b]};
        visit(a + b * nl.stride[1], s.w[0][a] * s.w[1][b], dS, {a, b});
      }
  } else {
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const RealLanes wbc = s.w[1][b] * s.w[2][c];
        for (int a = 0; a < N; ++a) {
          const RealLanes dS[3] = {s.dw[0][a] * wbc, s.w[0][a] * s.dw[1][b] * s.w[2][c],
                                   s.w[0][a] * s.w[1][b] * s.dw[2][c]};
          visit(a + b * nl.stride[1] + c * nl.stride[2], s.w[0][a] * wbc, dS, {a, b, c});
        }
      }
  }
}

}  // namespace mpm

#include "mpm/transfer/cpdi_lanes.hpp"  // LaneStencil and for_each_node of CPDI

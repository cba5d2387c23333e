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

/// The stencils of a block in lanes: base nodes, and per axis the weights and gradients [1/m] of each node.
template <int Dim, class Kernel>
struct LaneStencil {
  static constexpr int N = Kernel::width;
  static constexpr std::size_t node_count = Dim == 1 ? N : Dim == 2 ? N * N : N * N * N;  ///< nodes per stencil
  /// Node layers per axis of a tile's footprint: its own and those its particles' stencils reach above it.
  static constexpr int footprint = GridGeometry<Dim>::tile_width + N - 1;
  IntLanes node;  ///< flat index of each lane's base node
  IntLanes slot;  ///< flat index of each lane's base node in its tile's footprint (axis 0 fastest)
  RealLanes w[Dim][N], dw[Dim][N];

  [[gnu::always_inline]] LaneStencil(const std::vector<Stencil<Dim, Kernel>>& stencils, const LaneBlock& block, Real inv_h) {
    const StencilLanes<Dim, Kernel> s(block.load(stencils));
    node = s.node;
    using G = GridGeometry<Dim>;
    slot = IntLanes{};
    for (int d = Dim - 1; d >= 0; --d)
      slot = slot * footprint + ((s.tile_slot >> (G::tile_shift * d)) & (G::tile_width - 1));
    for (int d = 0; d < Dim; ++d) {
      Kernel::weights_at(s.axis[d], w[d], dw[d]);
      for (int a = 0; a < N; ++a) dw[d][a] *= inv_h;
    }
  }

  /// Lanes of get(node) at node (base + offset) of every lane.
  template <class Get>
  [[gnu::always_inline]] RealLanes gather(const std::vector<GridNode<Dim>>& nodes, std::int32_t offset, Get&& get) const {
    static_assert(sizeof(GridNode<Dim>) % sizeof(Real) == 0);
    return simd::gather(&get(nodes[0]), (node + offset) * reals_in<GridNode<Dim>>);
  }
};

/// Visit every node of the tensor-product stencils of a block: fn(offset of the node from each lane's base
/// node, weights S_ip, gradients grad S_ip [1/m] by axis). The same products as for_each_node, in lanes.
template <int Dim, class Kernel, class Fn>
[[gnu::always_inline]] inline void for_each_node(const LaneStencil<Dim, Kernel>& s, const NodeLayout<Dim>& nl, Fn&& fn) {
  constexpr int N = Kernel::width;
  if constexpr (Dim == 1) {
    for (int a = 0; a < N; ++a) {
      const RealLanes dS[1] = {s.dw[0][a]};
      fn(a, s.w[0][a], dS);
    }
  } else if constexpr (Dim == 2) {
    for (int b = 0; b < N; ++b)
      for (int a = 0; a < N; ++a) {
        const RealLanes dS[2] = {s.dw[0][a] * s.w[1][b], s.w[0][a] * s.dw[1][b]};
        fn(a + b * nl.stride[1], s.w[0][a] * s.w[1][b], dS);
      }
  } else {
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const RealLanes wbc = s.w[1][b] * s.w[2][c];
        for (int a = 0; a < N; ++a) {
          const RealLanes dS[3] = {s.dw[0][a] * wbc, s.w[0][a] * s.dw[1][b] * s.w[2][c],
                                   s.w[0][a] * s.w[1][b] * s.dw[2][c]};
          fn(a + b * nl.stride[1] + c * nl.stride[2], s.w[0][a] * wbc, dS);
        }
      }
  }
}

}  // namespace mpm

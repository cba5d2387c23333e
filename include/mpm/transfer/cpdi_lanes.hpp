#pragma once
/// CPDI's and CPDI2's stencils of a block in lanes and the visit of their nodes (Sadeghirad et al. 2011,
/// 2013; shape/cpdi.hpp, shape/cpdi2.hpp): the weights are sums over the domain's corners, not a tensor
/// product, so LaneStencil keeps the corners' hats (CornerWeights) and for_each_node sums them over the 4^Dim
/// nodes of the block. Included by transfer/lanes.hpp.
#include "mpm/shape/cpdi.hpp"
#include "mpm/transfer/lanes.hpp"

namespace mpm {

template <int Dim, class Kernel>
requires is_cpdi<Kernel>
struct LaneStencil<Dim, Kernel> : LaneNodes<Dim, Kernel> {
  static constexpr int N = Kernel::width;
  CornerWeights<Dim, RealLanes, Kernel> corners;
  RealLanes t[Dim];  ///< each particle's centre from its base node along each axis, in cells
  /// Set by locate_nodes (APIC only): dx[d][k] = x_i - x_p along axis d for the k-th node of the axis [m],
  /// and the inverse of the particle's inertia tensor D_p, a full matrix for a sheared domain.
  RealLanes dx[Dim][N], inv_D[Dim][Dim];

  [[gnu::always_inline]] LaneStencil(const ParticleStencils<Dim, Kernel>& stencils, const LaneBlock& block,
                                     const GridGeometry<Dim>& g, Real inv_h)
      : LaneStencil(stencils.lanes(block, g, inv_h), inv_h) {}
  [[gnu::always_inline]] LaneStencil(const StencilLanes<Dim, Kernel>& s, Real inv_h)
      : LaneNodes<Dim, Kernel>(s), corners(s.axis, inv_h) {
    for (int d = 0; d < Dim; ++d) t[d] = s.axis[d].t;
  }

  /// APIC's node offsets and D_p^-1 (Jiang et al. 2015): D_p = sum_i S_ip (x_i - x_p)(x_i - x_p)^T summed
  /// over the block. CPDI and CPDI2 put x_p at its domain's centroid, sum_i S_ip x_i, so the first moments
  /// vanish; D_p is positive definite for any domain of positive volume (for CPDI D_p >= R R^T).
  [[gnu::always_inline]] void locate_nodes(Real h) {
    for (int d = 0; d < Dim; ++d)
      for (int k = 0; k < N; ++k) dx[d][k] = (k - t[d]) * h;
    RealLanes D[Dim][Dim] = {};
    corners.visit([&](const int(&k)[Dim], const RealLanes& S, const RealLanes(&)[Dim])
                      __attribute__((always_inline)) {
                        for (int a = 0; a < Dim; ++a)
                          for (int b = 0; b < Dim; ++b) D[a][b] += S * dx[a][k[a]] * dx[b][k[b]];
                      });
    RealLanes C[Dim][Dim];
    cofactors(D, C);
    RealLanes det = D[0][0] * C[0][0];
    for (int k = 1; k < Dim; ++k) det += D[0][k] * C[0][k];
    const RealLanes inv = det > 0 ? 1 / det : RealLanes{};
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) inv_D[a][b] = C[b][a] * inv;  // D^-1 = C^T / det D
  }
};

/// Visit every node of the CPDI or CPDI2 stencils of a block, as for_each_node of the tensor-product kernels:
/// fn(offset of the node from each lane's base node, S_ip, grad S_ip [1/m], and the `moment` asked for).
template <NodeMoment moment = NodeMoment::none, int Dim, class Kernel, class Fn>
requires is_cpdi<Kernel>
[[gnu::always_inline]] inline void for_each_node(const LaneStencil<Dim, Kernel>& s, const NodeLayout<Dim>& nl,
                                                 Fn&& fn) {
  s.corners.visit([&](const int(&k)[Dim], const RealLanes& S, const RealLanes(&dS)[Dim])
                      __attribute__((always_inline)) {
                        std::int32_t offset = k[0];
                        for (int d = 1; d < Dim; ++d) offset += k[d] * nl.stride[d];
                        if constexpr (moment == NodeMoment::none) {
                          fn(offset, S, dS);
                        } else {
                          RealLanes Sx[Dim];
                          for (int d = 0; d < Dim; ++d) Sx[d] = S * s.dx[d][k[d]];
                          if constexpr (moment == NodeMoment::offset) {
                            fn(offset, S, dS, Sx);
                          } else {
                            RealLanes Sq[Dim];
                            for (int a = 0; a < Dim; ++a) {
                              Sq[a] = s.inv_D[a][0] * Sx[0];
                              for (int b = 1; b < Dim; ++b) Sq[a] += s.inv_D[a][b] * Sx[b];
                            }
                            fn(offset, S, dS, Sq);
                          }
                        }
                      });
}

}  // namespace mpm

#pragma once
/// Per-particle stencil: the base node and the 1-D weights and gradients along each axis, computed once per
/// particle per step and consumed by every transfer (P2G, G2P, re-projection).
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

template <int Dim, int N>
struct Stencil {
  std::int32_t node;                       ///< flat index of the base node
  std::int32_t layer;                      ///< storage index of the base node along the slowest axis
  std::array<std::array<Real, N>, Dim> w;  ///< 1-D weights per axis
  std::array<std::array<Real, N>, Dim> dw; ///< 1-D gradients per axis [1/m]
};

/// Flat strides of the grid, cached for the tensor-product loops.
template <int Dim>
struct Strides {
  std::array<std::int32_t, Dim> s;
  explicit Strides(const GridGeometry<Dim>& g) {
    for (int d = 0; d < Dim; ++d) s[d] = static_cast<std::int32_t>(g.stride(d));
  }
};

/// Compute the stencil of a particle at x with half-lengths l (used by GIMP only).
template <int Dim, class Kernel>
inline Stencil<Dim, Kernel::width> make_stencil(const GridGeometry<Dim>& g, const Strides<Dim>& st,
                                                 const Vec<Dim>& x, const Vec<Dim>& l) {
  Stencil<Dim, Kernel::width> s;
  const Real inv_h = 1 / g.h;
  std::int32_t node = 0;
  for (int d = 0; d < Dim; ++d) {
    const Real xi = (x[d] - g.lo[d]) * inv_h;
    const int base = Kernel::weights(xi, l[d] * inv_h, s.w[d].data(), s.dw[d].data());
    for (int k = 0; k < Kernel::width; ++k) s.dw[d][k] *= inv_h;
    node += (base + g.ghost) * st.s[d];
    if (d == Dim - 1) s.layer = base + g.ghost;
  }
  s.node = node;
  return s;
}

/// Stencils of all particles at their current positions and half-lengths, and the scatter strip of each
/// (ScatterOrder::strip_of its base node along the slowest axis). Returns whether any strip changed.
template <int Dim, class Kernel>
bool build_stencils(const ParticleSet<Dim>& p, const GridGeometry<Dim>& g,
                    std::vector<Stencil<Dim, Kernel::width>>& out, std::vector<std::int32_t>& strip) {
  const bool resized = strip.size() != p.size();
  out.resize(p.size());
  strip.resize(p.size(), -1);
  const Strides<Dim> st(g);
  std::atomic<bool> changed{resized};
  parallel_for(static_cast<std::ptrdiff_t>(p.size()), [&](std::ptrdiff_t i) {
    out[i] = make_stencil<Dim, Kernel>(g, st, p.x[i], p.l[i]);
    const std::int32_t s = ScatterOrder::strip_of<Kernel::width>(out[i].layer);
    if (s != strip[i]) {
      strip[i] = s;
      changed.store(true, std::memory_order_relaxed);
    }
  });
  return changed.load();
}

/// Visit every node of the tensor-product stencil: fn(flat node index, weight S_ip, gradient grad S_ip).
template <int Dim, int N, class Fn>
inline void for_each_node(const Stencil<Dim, N>& s, const Strides<Dim>& st, Fn&& fn) {
  if constexpr (Dim == 1) {
    for (int a = 0; a < N; ++a) fn(s.node + a, s.w[0][a], Vec<1>(s.dw[0][a]));
  } else if constexpr (Dim == 2) {
    for (int b = 0; b < N; ++b) {
      const std::int32_t row = s.node + b * st.s[1];
      for (int a = 0; a < N; ++a)
        fn(row + a, s.w[0][a] * s.w[1][b], Vec<2>(s.dw[0][a] * s.w[1][b], s.w[0][a] * s.dw[1][b]));
    }
  } else {
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const std::int32_t row = s.node + b * st.s[1] + c * st.s[2];
        const Real wbc = s.w[1][b] * s.w[2][c];
        for (int a = 0; a < N; ++a)
          fn(row + a, s.w[0][a] * wbc,
             Vec<3>(s.dw[0][a] * wbc, s.w[0][a] * s.dw[1][b] * s.w[2][c], s.w[0][a] * s.w[1][b] * s.dw[2][c]));
      }
  }
}

}  // namespace mpm

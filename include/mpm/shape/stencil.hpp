#pragma once
/// Per-particle stencil: the base node and the 1-D weights and gradients along each axis, computed once per
/// particle per step and consumed by every transfer (P2G, G2P, re-projection).
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/lanes.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/cpdi2.hpp"

namespace mpm {

template <int Dim, class Kernel>
struct Stencil {
  std::int32_t node;       ///< flat index of the base node
  std::int32_t tile_slot;  ///< the tile holding the base node and the base node's place in it
                           ///< (GridGeometry::slot_bits)
  std::array<typename Kernel::Axis, Dim> axis;  ///< per-axis data the kernel evaluates weights from
};

/// Whether a tensor-product kernel's weights depend on the particles' half-lengths l_p (GIMP's).
template <class Kernel>
inline constexpr bool weighs_half_lengths = requires {
  Kernel::max_half_length;
};

/// Whether a kernel reads the particles' half-lengths: GIMP's l_p, CPDI's l_p^0 (its domain vectors F_p
/// diag(l_p^0)) and CPDI2's, from which its corners are first placed. The others leave ParticleSet::l0 empty.
template <class Kernel>
inline constexpr bool reads_half_lengths = weighs_half_lengths<Kernel> || is_cpdi<Kernel>;

/// Whether a particle keeps its stencil's axis data from the stencil's locate to its use: CPDI's and CPDI2's,
/// whose locate reads the whole domain. A tensor-product kernel's particle keeps the base node and tile; the
/// axis data is located again where it is read, from the particle's position and half-lengths, which do not
/// change in between (USF excepted, which keeps its half-lengths: ParticleStencils): the same bits.
template <class Kernel>
inline constexpr bool keeps_axes = is_cpdi<Kernel>;

/// What a tensor-product kernel's particle keeps of its stencil: the base node and tile (Stencil's first two
/// members).
struct StencilIndex {
  std::int32_t node;
  std::int32_t tile_slot;
};

/// What a particle keeps of its stencil between the stencil's locate and its use.
template <int Dim, class Kernel>
using StoredStencil = std::conditional_t<keeps_axes<Kernel>, Stencil<Dim, Kernel>, StencilIndex>;

/// Stencils in SIMD lanes (LaneBlock::load and store): Real 0 holds node (low half) and layer (high half),
/// then come the Reals the record keeps (StoredStencil): each axis's.
template <int Dim, class Kernel>
struct StencilLanes {
  using AxisLanes = typename Kernel::template AxisOf<RealLanes>;
  static constexpr int axis_reals = reals_in<typename Kernel::Axis>;
  using StencilT = Stencil<Dim, Kernel>;
  static_assert(sizeof(StencilT) == (1 + Dim * axis_reals) * sizeof(Real) &&
                    offsetof(StencilT, tile_slot) == 4 && sizeof(AxisLanes) == axis_reals * sizeof(RealLanes),
                "a stencil is two 32-bit indices and Dim axes of Reals; AxisOf holds only its T members");

  IntLanes node, tile_slot;
  AxisLanes axis[Dim];

  StencilLanes() = default;
  /// The records a block's particles keep (StoredStencil): indices, and the axis data they hold.
  explicit StencilLanes(const RecordLanes<StoredStencil<Dim, Kernel>>& r) {
    const IntLanes indices = reinterpret_cast<IntLanes>(r[0]);
    node = (indices << 32) >> 32;  // sign-extended low half
    tile_slot = indices >> 32;
    if constexpr (keeps_axes<Kernel>) {
      for (int d = 0; d < Dim; ++d) {
        std::array<RealLanes, axis_reals> members;
        for (int j = 0; j < axis_reals; ++j) members[j] = r[1 + d * axis_reals + j];
        axis[d] = std::bit_cast<AxisLanes>(members);
      }
    }
  }
  /// The records to keep (StoredStencil).
  RecordLanes<StoredStencil<Dim, Kernel>> stored() const {
    RecordLanes<StoredStencil<Dim, Kernel>> r;
    r[0] = reinterpret_cast<RealLanes>((tile_slot << 32) | (node & 0xffffffff));
    if constexpr (keeps_axes<Kernel>) {
      for (int d = 0; d < Dim; ++d) {
        const auto members = std::bit_cast<std::array<RealLanes, axis_reals>>(axis[d]);
        for (int j = 0; j < axis_reals; ++j) r[1 + d * axis_reals + j] = members[j];
      }
    }
    return r;
  }
};

/// Flat strides of nodes and tiles and inverse cell width of a grid, cached for the tensor-product loops.
template <int Dim>
struct NodeLayout {
  std::array<std::int32_t, Dim> stride, tile_stride;
  Real inv_h;
  explicit NodeLayout(const GridGeometry<Dim>& g) : inv_h(1 / g.h) {
    std::int32_t tiles = 1;
    for (int d = 0; d < Dim; ++d) {
      stride[d] = static_cast<std::int32_t>(g.stride(d));
      tile_stride[d] = tiles;
      tiles *= g.tiles_along(d);
    }
  }
};

/// The base node along axis d (a global index) of a position xi in grid units with half-length l, and the
/// kernel's axis data: Kernel::locate, then at the faces the geometry clamps (GridGeometry::clamped,
/// B-splines only), the base node held inside, so that the stencil ends on the face's node (the kernel folds
/// its weights). For one position or lanes of them.
template <class Kernel, int Dim, class T>
[[gnu::always_inline]] inline auto locate_axis(const GridGeometry<Dim>& g, int d, const T& xi, const T& l,
                                               typename Kernel::template AxisOf<T>& a) {
  auto base = Kernel::locate(xi, l, a);
  if constexpr (requires { Kernel::rebase(a, xi); }) {
    const bool lower = g.clamped[2 * d], upper = g.clamped[2 * d + 1];
    if (lower || upper) {
      using Index = decltype(base);
      const Index first = Index{} + (lower ? 0 : -(1 << 30));
      const Index last = Index{} + (upper ? g.cells[d] - Kernel::width + 1 : 1 << 30);
      const Index held = simd::min(simd::max(base, first), last);
      Kernel::rebase(a, simd::to_real(base - held));
      base = held;
    }
  }
  return base;
}

/// What locates a particle's stencil besides its position: the half-lengths l_p of a tensor-product kernel
/// (GIMP's domain, ParticleSet::half_length; the others ignore them), CPDI's domain vectors R = [r_1 ... r_D]
/// = F_p diag(l_p0) (Sadeghirad et al. 2011), or CPDI2's corners (Sadeghirad et al. 2013).
template <int Dim, class Kernel>
using Domain = std::conditional_t<moves_corners<Kernel>, Corners<Dim>,
                                  std::conditional_t<is_cpdi<Kernel>, Mat<Dim>, Vec<Dim>>>;

/// Particle i's Domain.
template <int Dim, class Kernel>
Domain<Dim, Kernel> domain_of(const ParticleSet<Dim>& p, std::size_t i) {
  if constexpr (moves_corners<Kernel>)
    return p.corners[i];
  else if constexpr (is_cpdi<Kernel>)
    return p.F[i] * p.l0[i].asDiagonal();
  else
    return p.half_length(i);
}

/// The Domains of a block of particles, in lanes (Mat is column-major: entry (a, k) is Real a + k Dim).
template <int Dim, class Kernel>
[[gnu::always_inline]] inline RecordLanes<Domain<Dim, Kernel>> load_domain(const LaneBlock& block,
                                                                           const ParticleSet<Dim>& p) {
  if constexpr (moves_corners<Kernel>) {
    return block.load(p.corners);
  } else if constexpr (is_cpdi<Kernel>) {
    RecordLanes<Mat<Dim>> R = block.load(p.F);
    const RecordLanes<Vec<Dim>> l0 = block.load(p.l0);
    for (int k = 0; k < Dim; ++k)
      for (int a = 0; a < Dim; ++a) R[a + k * Dim] *= l0[k];
    return R;
  } else if constexpr (reads_half_lengths<Kernel>) {
    RecordLanes<Vec<Dim>> l = block.load(p.l0);
    if (p.half_lengths == HalfLengths::deformed)  // Wallstedt & Guilkey 2008, Eq. (63), of F's diagonal alone
      for (int d = 0; d < Dim; ++d)
        l[d] = deformed_half_length(l[d], block.load_member(p.F, d + d * Dim), p.max_half_length);
    return l;
  } else {
    return RecordLanes<Vec<Dim>>{};  // the kernel ignores them
  }
}

/// The base nodes (global indices) and axis data of particles at x with domains `domain`, for one particle (T
/// = Real, x and domain Eigen values) or lanes (T = RealLanes, x and domain RecordLanes): locate_axis along
/// each axis for a tensor-product kernel, CpdiKernel::locate of the domain in cells for CPDI,
/// Cpdi2Kernel::locate of the corners' places from x in cells for CPDI2 (Corners is column-major: coordinate
/// d of corner c is Real d + c Dim).
template <class Kernel, int Dim, class T, class X, class D>
[[gnu::always_inline]] inline auto locate_stencil(const GridGeometry<Dim>& g, Real inv_h, const X& x,
                                                  const D& domain,
                                                  typename Kernel::template AxisOf<T> (&axis)[Dim]) {
  T xi[Dim];
  for (int d = 0; d < Dim; ++d) xi[d] = (x[d] - g.lo[d]) * inv_h;
  if constexpr (moves_corners<Kernel>) {
    T offset[Kernel::corners][Dim];
    for (int c = 0; c < Kernel::corners; ++c)
      for (int d = 0; d < Dim; ++d) offset[c][d] = (domain[d + c * Dim] - x[d]) * inv_h;
    return Kernel::locate(xi, offset, axis);
  } else if constexpr (is_cpdi<Kernel>) {
    T R[Dim][Dim];
    for (int a = 0; a < Dim; ++a)
      for (int k = 0; k < Dim; ++k) R[a][k] = domain[a + k * Dim] * inv_h;
    return Kernel::locate(xi, R, axis);
  } else {
    std::array<decltype(simd::floor_index(xi[0])), Dim> base;
    for (int d = 0; d < Dim; ++d) base[d] = locate_axis<Kernel>(g, d, xi[d], domain[d] * inv_h, axis[d]);
    return base;
  }
}

/// Compute the stencil of a particle at x with domain `domain` (Domain).
template <int Dim, class Kernel>
inline Stencil<Dim, Kernel> make_stencil(const GridGeometry<Dim>& g, const NodeLayout<Dim>& nl,
                                         const Vec<Dim>& x, const Domain<Dim, Kernel>& domain) {
  Stencil<Dim, Kernel> s;
  using G = GridGeometry<Dim>;
  typename Kernel::Axis axis[Dim];
  const auto base = locate_stencil<Kernel, Dim, Real>(g, nl.inv_h, x, domain.data(), axis);
  std::int32_t node = 0, tile = 0, slot = 0;
  for (int d = 0; d < Dim; ++d) {
    s.axis[d] = axis[d];
    const int layer = base[d] + g.ghost - g.offset[d];  // storage index in this box
    node += layer * nl.stride[d];
    tile += (layer >> G::tile_shift) * nl.tile_stride[d];
    slot |= (layer & (G::tile_width - 1)) << (G::tile_shift * d);
  }
  s.node = node;
  s.tile_slot = (tile << G::slot_bits) | slot;
  return s;
}

/// What a particle at x with domain `domain` keeps of its stencil (StoredStencil of make_stencil's).
template <int Dim, class Kernel>
StoredStencil<Dim, Kernel> make_stored_stencil(const GridGeometry<Dim>& g, const NodeLayout<Dim>& nl,
                                               const Vec<Dim>& x, const Domain<Dim, Kernel>& domain) {
  const Stencil<Dim, Kernel> s = make_stencil<Dim, Kernel>(g, nl, x, domain);
  if constexpr (keeps_axes<Kernel>) {
    return s;
  } else {
    return StencilIndex{s.node, s.tile_slot};
  }
}

/// The stencils of a block of particles at positions x with domains `domain` (load_domain): make_stencil's
/// arithmetic in lanes.
template <int Dim, class Kernel>
[[gnu::always_inline]] inline StencilLanes<Dim, Kernel> locate_block(
    const GridGeometry<Dim>& g, const NodeLayout<Dim>& nl, const RecordLanes<Vec<Dim>>& x,
    const RecordLanes<Domain<Dim, Kernel>>& domain) {
  StencilLanes<Dim, Kernel> s;
  using G = GridGeometry<Dim>;
  const auto base = locate_stencil<Kernel, Dim, RealLanes>(g, nl.inv_h, x, domain, s.axis);
  s.node = IntLanes{};
  IntLanes tile{}, slot{};
  for (int d = 0; d < Dim; ++d) {
    const IntLanes layer = base[d] + (g.ghost - g.offset[d]);  // storage index in this box
    s.node += layer * nl.stride[d];
    tile += (layer >> G::tile_shift) * nl.tile_stride[d];
    slot |= (layer & (G::tile_width - 1)) << (G::tile_shift * d);
  }
  s.tile_slot = (tile << G::slot_bits) | slot;
  return s;
}

/// The tiles of stored stencils, as ScatterOrder::build reads them: tile[i] is the flat index of the tile
/// holding stencil i's base node in the box.
template <int Dim, class Kernel>
struct StencilTiles {
  const std::vector<StoredStencil<Dim, Kernel>>& stored;
  std::size_t size() const { return stored.size(); }
  std::int32_t operator[](std::size_t i) const { return stored[i].tile_slot >> GridGeometry<Dim>::slot_bits; }
};

/// Where stencils go: one per particle, and whether any particle changed tile (its base node's, for
/// ScatterOrder).
template <int Dim, class Kernel>
struct StencilTargets {
  std::vector<StoredStencil<Dim, Kernel>>& stencils;
  std::atomic<bool> tile_changed{false};

  /// Store the stencils of a block of particles in place of their last ones.
  [[gnu::always_inline]] void store(const LaneBlock& block, const StencilLanes<Dim, Kernel>& s) {
    // Real 0 of a record holds node (low half) and tile_slot (high half); lanes past the last particle repeat
    // it.
    const RealLanes last =
        reals_in<StoredStencil<Dim, Kernel>> == 1 ? block.load(stencils)[0] : block.load_member(stencils, 0);
    constexpr int shift = 32 + GridGeometry<Dim>::slot_bits;
    const bool moved = simd::any((std::bit_cast<IntLanes>(last) >> shift) != ((s.tile_slot << 32) >> shift));
    block.store(stencils, s.stored());
    if (moved) tile_changed.store(true, std::memory_order_relaxed);
  }
};

/// Stencils of all particles at their current positions and domains, computed in LaneBlocks. Returns whether
/// any tile changed (or the particles' count did).
template <int Dim, class Kernel>
bool build_stencils(const ParticleSet<Dim>& p, const GridGeometry<Dim>& g,
                    std::vector<StoredStencil<Dim, Kernel>>& out) {
  const bool resized = out.size() != p.size();
  out.resize(p.size());
  const NodeLayout<Dim> nl(g);
  StencilTargets<Dim, Kernel> targets{out, resized};
  parallel_for(
      LaneBlock::count(p.size()),
      [&](std::ptrdiff_t b) {
        const LaneBlock block(b, static_cast<std::ptrdiff_t>(p.size()));
        targets.store(block,
                      locate_block<Dim, Kernel>(g, nl, block.load(p.x), load_domain<Dim, Kernel>(block, p)));
      },
      1024 / LaneBlock::width);
  return targets.tile_changed.load();
}

/// The stencils of a particle set as the transfers read them: what each particle keeps (StoredStencil), and
/// the particles, whose positions and half-lengths give the axis data the records do not keep. A USF step
/// changes F, and so cpGIMP's half-lengths l_p^0 diag(F_p), in its deformation pass and reads the stencils
/// again in its force pass: it hands the half-lengths of the locate over in `located_half_lengths` (null: the
/// particles' current ones).
template <int Dim, class Kernel>
struct ParticleStencils {
  const std::vector<StoredStencil<Dim, Kernel>>& stored;
  const ParticleSet<Dim>& particles;
  const std::vector<Vec<Dim>>* located_half_lengths = nullptr;

  std::size_t size() const { return stored.size(); }
  /// The stencils of a block in lanes, their axis data located again where the records keep none:
  /// locate_block's arithmetic on the same positions and half-lengths, so the same bits.
  [[gnu::always_inline]] StencilLanes<Dim, Kernel> lanes(const LaneBlock& block, const GridGeometry<Dim>& g,
                                                         Real inv_h) const {
    StencilLanes<Dim, Kernel> s(block.load(stored));
    if constexpr (!keeps_axes<Kernel>) {
      RecordLanes<Vec<Dim>> l{};  // the kernels that do not weigh half-lengths ignore them
      if constexpr (weighs_half_lengths<Kernel>)
        l = located_half_lengths ? block.load(*located_half_lengths)
                                 : load_domain<Dim, Kernel>(block, particles);
      locate_stencil<Kernel, Dim, RealLanes>(g, inv_h, block.load(particles.x), l, s.axis);
    }
    return s;
  }
  /// Particle i's stencil, axis data included: make_stencil's arithmetic on what locate_block did in lanes.
  Stencil<Dim, Kernel> at(std::size_t i, const GridGeometry<Dim>& g, const NodeLayout<Dim>& nl) const {
    if constexpr (keeps_axes<Kernel>) {
      return stored[i];
    } else {
      Vec<Dim> l = Vec<Dim>::Zero();
      if constexpr (weighs_half_lengths<Kernel>)
        l = located_half_lengths ? (*located_half_lengths)[i] : particles.half_length(i);
      return make_stencil<Dim, Kernel>(g, nl, particles.x[i], l);
    }
  }
};

/// Visit every node of the tensor-product stencil: fn(flat node index, weight S_ip, gradient grad S_ip
/// [1/m]).
template <int Dim, class Kernel, class Fn>
inline void for_each_node(const Stencil<Dim, Kernel>& s, const NodeLayout<Dim>& nl, Fn&& fn) {
  constexpr int N = Kernel::width;
  Real w[Dim][N], dw[Dim][N];
  for (int d = 0; d < Dim; ++d) {
    Kernel::weights_at(s.axis[d], w[d], dw[d]);
    for (int k = 0; k < N; ++k) dw[d][k] *= nl.inv_h;
  }
  if constexpr (Dim == 1) {
    for (int a = 0; a < N; ++a) fn(s.node + a, w[0][a], Vec<1>(dw[0][a]));
  } else if constexpr (Dim == 2) {
    for (int b = 0; b < N; ++b) {
      const std::int32_t row = s.node + b * nl.stride[1];
      for (int a = 0; a < N; ++a)
        fn(row + a, w[0][a] * w[1][b], Vec<2>(dw[0][a] * w[1][b], w[0][a] * dw[1][b]));
    }
  } else {
    for (int c = 0; c < N; ++c)
      for (int b = 0; b < N; ++b) {
        const std::int32_t row = s.node + b * nl.stride[1] + c * nl.stride[2];
        const Real wbc = w[1][b] * w[2][c];
        for (int a = 0; a < N; ++a)
          fn(row + a, w[0][a] * wbc,
             Vec<3>(dw[0][a] * wbc, w[0][a] * dw[1][b] * w[2][c], w[0][a] * w[1][b] * dw[2][c]));
      }
  }
}

/// Visit every node of a CPDI or CPDI2 stencil's block: fn(flat node index, weight S_ip, gradient grad S_ip
/// [1/m]) (CornerWeights).
template <int Dim, class Kernel, class Fn>
requires is_cpdi<Kernel>
inline void for_each_node(const Stencil<Dim, Kernel>& s, const NodeLayout<Dim>& nl, Fn&& fn) {
  const CornerWeights<Dim, Real, Kernel> weights(s.axis, nl.inv_h);
  weights.visit([&](const int(&k)[Dim], Real S, const Real(&dS)[Dim]) {
    std::int32_t node = s.node;
    Vec<Dim> grad;
    for (int d = 0; d < Dim; ++d) {
      node += k[d] * nl.stride[d];
      grad[d] = dS[d];
    }
    fn(node, S, grad);
  });
}

}  // namespace mpm

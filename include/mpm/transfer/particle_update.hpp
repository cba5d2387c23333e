#pragma once
/// The particle update both engines share, in SIMD lanes: a new position kept to the grid (a periodic wrap, a
/// wall's plane, the faces it may not pass), CPDI2's centroid with the corners following it, the deformation
/// gradient and its determinant, and cpGIMP's half-lengths checked against the stencil. The explicit G2P pass
/// (transfer/g2p.hpp) calls it on the sums it gathers, the implicit step's acceptance on the converged
/// solution's.
#include <atomic>
#include <cstdint>
#include <limits>

#include "mpm/core/simd.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/lanes.hpp"
#include "mpm/shape/cpdi2.hpp"
#include "mpm/shape/kernels.hpp"

namespace mpm {

/// Where a grid lets a particle go: a periodic axis wraps it (out through one face, in through the other), a
/// wall holds it on the wall's plane, and it may pass no other face but an outflow face.
template <int Dim>
struct PositionBounds {
  explicit PositionBounds(const GridGeometry<Dim>& geo) : lo(geo.lo) {
    for (int c = 0; c < Dim; ++c) {
      const Real inf = std::numeric_limits<Real>::infinity();
      if (geo.periodic[c]) wraps = true, period[c] = geo.h * geo.cells[c];
      lo_bound[c] = geo.outflow[2 * c] ? -inf : geo.lo[c];
      hi_bound[c] = geo.outflow[2 * c + 1] ? inf : geo.lo[c] + geo.h * geo.cells[c];
      walls[2 * c] = geo.walls[2 * c];
      walls[2 * c + 1] = geo.walls[2 * c + 1];
    }
  }

  /// x wrapped and put back onto the walls' planes; the lanes whose x then lies within the bounds.
  [[gnu::always_inline]] simd::MaskLanes keep(RecordLanes<Vec<Dim>>& x) const {
    simd::MaskLanes inside = simd::MaskLanes{} == 0;  // all lanes true
    for (int c = 0; c < Dim; ++c) {
      if (wraps && period[c] > 0) {
        x[c] = x[c] >= lo[c] + period[c] ? x[c] - period[c] : x[c];
        x[c] = x[c] < lo[c] ? x[c] + period[c] : x[c];
      }
      if (walls[2 * c]) {
        const RealLanes bound = simd::broadcast(lo_bound[c]);
        x[c] = x[c] < bound ? bound : x[c];
      }
      if (walls[2 * c + 1]) {
        const RealLanes bound = simd::broadcast(hi_bound[c]);
        x[c] = x[c] > bound ? bound : x[c];
      }
      inside &= (x[c] >= lo_bound[c]) & (x[c] <= hi_bound[c]);
    }
    return inside;
  }

  Vec<Dim> lo;
  bool wraps = false;  ///< some axis is periodic: the wrap costs a register test on grids without one
  Vec<Dim> period = Vec<Dim>::Zero(), lo_bound, hi_bound;  ///< bounds +-inf beyond outflow faces
  bool walls[2 * Dim];
};

/// The new positions of a block: x + dt v, or for CPDI2 the centroid of its moved corners (Sadeghirad et al.
/// 2013), kept to the grid, the corners following the centroid through a wrap or onto a wall. `v` is indexed
/// by axis (lanes of a velocity); `corners` is read and written by CPDI2 only. Returns the lanes that stay
/// within the bounds with an unfolded domain.
template <int Dim, class Kernel, class Velocity>
[[gnu::always_inline]] inline simd::MaskLanes move_positions(
    const PositionBounds<Dim>& bounds, RecordLanes<Vec<Dim>>& x, const Velocity& v, Real dt,
    [[maybe_unused]] RecordLanes<Corners<Dim>>& corners) {
  simd::MaskLanes ok = simd::MaskLanes{} == 0;
  [[maybe_unused]] RealLanes centroid[Dim];
  if constexpr (moves_corners<Kernel>) {
    RealLanes xc[Kernel::corners][Dim], near[Dim];
    for (int c = 0; c < Kernel::corners; ++c)
      for (int d = 0; d < Dim; ++d) xc[c][d] = corners[d + c * Dim];
    for (int d = 0; d < Dim; ++d) near[d] = x[d];
    ok &= corner_centroid<Dim>(xc, near, centroid);
    for (int d = 0; d < Dim; ++d) x[d] = centroid[d];
  } else {
    for (int c = 0; c < Dim; ++c) x[c] += dt * v[c];
  }
  ok &= bounds.keep(x);
  if constexpr (moves_corners<Kernel>)
    for (int c = 0; c < Kernel::corners; ++c)
      for (int d = 0; d < Dim; ++d) corners[d + c * Dim] += x[d] - centroid[d];
  return ok;
}

/// F^{n+1} = (I + dt grad v) F^n by entry (Wallstedt & Guilkey 2008, Eq. (11)), with grad_v(a, c) = d v_a /
/// d x_c, into F and F_new (Mat is column-major: entry (a, c) is Real a + c Dim); returns det F^{n+1}.
template <int Dim, class Gradient>
[[gnu::always_inline]] inline RealLanes deform(const Gradient& grad_v, Real dt,
                                               const RecordLanes<Mat<Dim>>& F_old, RealLanes (&F)[Dim][Dim],
                                               RecordLanes<Mat<Dim>>& F_new) {
  for (int a = 0; a < Dim; ++a)
    for (int c = 0; c < Dim; ++c) {
      F[a][c] = ((a == 0 ? 1 : 0) + dt * grad_v(a, 0)) * F_old[c * Dim];
      for (int e = 1; e < Dim; ++e) F[a][c] += ((a == e ? 1 : 0) + dt * grad_v(a, e)) * F_old[e + c * Dim];
      F_new[a + c * Dim] = F[a][c];
    }
  return simd::determinant(F);
}

/// Lower `first_fault` to the index of the block's first lane that is not `ok`, if lower (several threads
/// may record at once; the lowest index wins, whatever the order).
[[gnu::always_inline]] inline void note_first_fault(std::atomic<std::int64_t>& first_fault,
                                                    const LaneBlock& block, const simd::MaskLanes& ok) {
  std::int64_t fault = std::numeric_limits<std::int64_t>::max();
  for (int k = block.active - 1; k >= 0; --k)
    if (!ok[k]) fault = block.index[k];
  std::int64_t cur = first_fault.load(std::memory_order_relaxed);
  while (fault < cur && !first_fault.compare_exchange_weak(cur, fault)) {
  }
}

}  // namespace mpm

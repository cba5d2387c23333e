#pragma once
/// The division of a grid between ranks: boxes of whole tiles (GridGeometry::tile_width node layers per
/// axis), one per rank, found by recursive coordinate bisection weighted by the particles in each tile. Whole
/// tiles, because a P2G pass sums each tile's particles apart (ScatterOrder): a rank that owns a set of whole
/// tiles computes the same tile sums as one process, so the node sums are the same bits whatever the
/// division.
#include <cstdint>
#include <vector>

#include "mpm/core/types.hpp"

namespace mpm {

/// The tiles [lo, hi) along each axis, in global tile coordinates.
template <int Dim>
struct TileBox {
  IVec<Dim> lo{}, hi{};

  bool contains(const IVec<Dim>& t) const {
    for (int d = 0; d < Dim; ++d)
      if (t[d] < lo[d] || t[d] >= hi[d]) return false;
    return true;
  }
  std::int64_t tile_count() const {
    std::int64_t n = 1;
    for (int d = 0; d < Dim; ++d) n *= hi[d] - lo[d];
    return n;
  }
  bool operator==(const TileBox&) const = default;
};

/// Divide a grid of `tiles` tiles per axis into `ranks` boxes by recursive coordinate bisection (Berger &
/// Bokhari 1987): a box for n ranks is cut across its longest axis (in tiles; the lowest such axis on a tie)
/// into boxes for floor(n/2) and n - floor(n/2) ranks, at the tile layer that shares `weight` between them
/// closest to that ratio (on a tie, the layer nearest the proportional cut of the box's length), and so on
/// until each box has one rank. `weight[t]` is the work of tile t (its particles), flat with axis 0 fastest.
/// Box r is rank r's. A cut across axis d lies at a tile layer no higher than cut_limit[d] (cut_limit in
/// box_halo.hpp; an axis with no such layer is not cut). The result depends only on the arguments. Throws
/// InputError when a box for several ranks cannot be cut (more ranks than the grid can be cut into).
template <int Dim>
std::vector<TileBox<Dim>> bisect(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight, int ranks,
                                 const IVec<Dim>& cut_limit);
/// bisect with no limit on the cuts.
template <int Dim>
std::vector<TileBox<Dim>> bisect(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight, int ranks) {
  return bisect<Dim>(tiles, weight, ranks, tiles);
}

/// The largest box's weight over the mean weight per rank (1: balanced; 1 when there is no weight at all).
template <int Dim>
double imbalance(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight,
                 const std::vector<TileBox<Dim>>& boxes);

}  // namespace mpm

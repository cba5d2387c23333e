#pragma once
/// One rank's box of a divided grid and its halo sum. The box (whole tiles, decomposition.hpp) holds its
/// tiles' node layers and the width - 1 layers above them that its particles' stencils reach (box_geometry).
/// After a P2G pass every node a tile of another box also reaches gets, on every box that holds it, the sums
/// of all the tiles that reach it added in colour order from zero: one process's value (ScatterOrder). Each
/// box sends the kept sums of its face tiles (FaceTileSums) to the boxes whose grids they reach, one exchange
/// with those neighbours per pass; the boxes then hold the same bits on the nodes they share, and the grid
/// update, the boundary conditions and G2P need no second exchange.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "mpm/core/exact_sum.hpp"
#include "mpm/core/types.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/distributed/decomposition.hpp"
#include "mpm/distributed/tile_halo.hpp"
#include "mpm/grid/grid.hpp"

namespace mpm {

template <int Dim>
class BoxHalo {
 public:
  /// One process: the whole grid is the one box.
  explicit BoxHalo(const GridGeometry<Dim>& whole) : whole_(whole), box_(whole) {}
  /// Rank `rank`'s box of `boxes` (bisect), for a kernel `width` nodes wide.
  BoxHalo(const GridGeometry<Dim>& whole, std::vector<TileBox<Dim>> boxes, int rank, int width);

  /// Whether the grid is divided (more than one box).
  bool divided() const { return boxes_.size() > 1; }
  const GridGeometry<Dim>& whole() const { return whole_; }
  /// This rank's box of the grid.
  const GridGeometry<Dim>& box() const { return box_; }
  const std::vector<TileBox<Dim>>& boxes() const { return boxes_; }
  /// The ranks whose boxes' grids share nodes with this one's (ascending): the halo sum's only partners. A
  /// particle that moves less than a tile stays in this box or moves to one of theirs.
  const std::vector<int>& peers() const { return peers_; }
  /// The storage layers per axis of this box's grid that its own tiles hold (the rest are other boxes').
  IVec<Dim> owned_layers() const {
    IVec<Dim> n;
    for (int d = 0; d < Dim; ++d)
      n[d] = divided() ? std::min(box_.nodes_along(d),
                                  GridGeometry<Dim>::tile_width * (boxes_[rank_].hi[d] - boxes_[rank_].lo[d]))
                       : box_.nodes_along(d);
    return n;
  }
  /// The rank that owns the tile holding global storage node layer s (per axis).
  int owner(const IVec<Dim>& s) const {
    std::int64_t flat = 0;
    for (int d = Dim - 1; d >= 0; --d)
      flat = flat * whole_.tiles_along(d) + (s[d] >> GridGeometry<Dim>::tile_shift);
    return owner_[static_cast<std::size_t>(flat)];
  }

  /// Whether a particle at x certainly has its stencil's base node in this box's own tiles: x lies at least
  /// three cells inside the nodes of those tiles along every axis (a base node lies at most two cells below
  /// the particle's cell for every kernel). Only the particles near the box's faces need locating to find
  /// their owner.
  bool surely_owned(const Vec<Dim>& x) const {
    for (int d = 0; d < Dim; ++d)
      if (!(x[d] >= inner_lo_[d] && x[d] < inner_hi_[d])) return false;
    return true;
  }

  /// After a P2G pass of the fields `mass_momentum` (m, momentum) and/or `force` onto cleared fields, with
  /// the sums of this box's face tiles `kept`: the halo sum over `comm`. A force pass that adds onto an
  /// earlier pass's sums instead (the hoop force in axisymmetry) gives `force_base`, every node's force
  /// before it: a shared node then starts from that rather than zero, as one process's pass adds onto it. A
  /// mass pass that scattered the volume gradient into v_new for contact sums it too (`volume_gradient`).
  void sum(Grid<Dim>& grid, std::vector<TileSums<Dim>> kept, bool mass_momentum, bool force,
           const Communicator& comm, const std::vector<Vec<Dim>>* force_base = nullptr,
           bool volume_gradient = false) const;

 private:
  GridGeometry<Dim> whole_, box_;
  std::vector<TileBox<Dim>> boxes_;
  std::vector<IVec<Dim>> first_, end_;  ///< each box's grid: global storage layers [first, end) per axis
  std::vector<std::int32_t> owner_;     ///< rank of each tile of the whole grid (flat, axis 0 fastest)
  std::vector<int> peers_;
  Vec<Dim> inner_lo_ = Vec<Dim>::Zero(), inner_hi_ = Vec<Dim>::Zero();  ///< surely_owned's bounds [m]
  int rank_ = 0;
};

/// Numbers summed exactly on each rank, added over the ranks and rounded once: the same bits whatever the
/// division.
inline std::vector<Real> sum_over_ranks(const std::vector<ExactSum>& sums, const Communicator& comm) {
  std::vector<std::int64_t> integers;
  for (const ExactSum& e : sums) {
    const std::vector<std::int64_t> mine = e.integers();
    integers.insert(integers.end(), mine.begin(), mine.end());
  }
  comm.sum(integers);
  std::vector<Real> out(sums.size());
  auto at = integers.begin();
  for (Real& r : out) {
    r = ExactSum::from_integers({at, at + ExactSum::integer_count}).value();
    at += ExactSum::integer_count;
  }
  return out;
}

/// The same for rows of N sums (the moments of a constraint, the forces of a contact pair), in one exchange.
template <std::size_t N>
std::vector<std::array<Real, N>> sum_rows_over_ranks(const std::vector<std::array<ExactSum, N>>& sums,
                                                     const Communicator& comm) {
  std::vector<ExactSum> flat;
  for (const std::array<ExactSum, N>& r : sums) flat.insert(flat.end(), r.begin(), r.end());
  const std::vector<Real> total = sum_over_ranks(flat, comm);
  std::vector<std::array<Real, N>> out(sums.size());
  for (std::size_t k = 0; k < out.size(); ++k)
    std::copy_n(total.begin() + static_cast<std::ptrdiff_t>(k * N), N, out[k].begin());
  return out;
}

/// The same for vectors (a reaction per constraint).
template <int Dim>
std::vector<Vec<Dim>> sum_over_ranks(const std::vector<std::array<ExactSum, Dim>>& sums,
                                     const Communicator& comm) {
  std::vector<Vec<Dim>> out;
  for (const std::array<Real, Dim>& r : sum_rows_over_ranks(sums, comm))
    out.push_back(Eigen::Map<const Vec<Dim>>(r.data()));
  return out;
}

/// The largest tile layer along each axis a cut between boxes may lie at (bisect's `cut_limit`): below a
/// symmetry plane on a high face, so that a box that holds any node the plane's fold pairs holds them all
/// (Steffen et al. 2008, Sec. 3.4.2: ghost and mirror node within `ghost` layers of the plane).
/// `symmetric_high[d]`: the high face of axis d is a symmetry plane.
template <int Dim>
IVec<Dim> cut_limit(const GridGeometry<Dim>& whole, const std::array<bool, Dim>& symmetric_high, int width) {
  IVec<Dim> limit;
  for (int d = 0; d < Dim; ++d) {
    limit[d] = whole.tiles_along(d);
    // A cut at tile layer t starts the upper box at storage layer 8t, and the lower box's grid reaches
    // 8t + width - 2; the fold pairs storage layers [cells, cells + 2 ghost]: the lower box must end below
    // them.
    if (symmetric_high[d]) limit[d] = (whole.cells[d] - width + 1) >> GridGeometry<Dim>::tile_shift;
  }
  return limit;
}

}  // namespace mpm

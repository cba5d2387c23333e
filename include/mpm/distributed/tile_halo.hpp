#pragma once
/// The grid of one box and the halo sum after P2G, kept equal to one process's sums bit for bit.
///
/// A box (whole tiles, decomposition.hpp) holds its tiles' node layers and the width - 1 layers above them
/// that its particles' stencils reach. Its P2G gives every node the sums of the box's own tiles. A node near
/// the box's lower faces is also reached by tiles of the boxes below, and the node above the box's upper
/// faces belong to other boxes: there the value of one process, the tiles' sums added in colour order
/// (ScatterOrder), needs the sums of each tile apart. So each box keeps the sums of its face tiles
/// (TileSums), and every box that holds a node that tiles of several boxes reach adds all their sums in
/// colour order (BoxHalo::sum exchanges them).
#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "mpm/distributed/decomposition.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace mpm {

/// The geometry of `box` of grid g for a kernel `width` nodes wide: its tiles' node layers and the width - 1
/// above them, cut at the grid's last layer; offset = the box's first layer.
template <int Dim>
GridGeometry<Dim> box_geometry(const GridGeometry<Dim>& g, const TileBox<Dim>& box, int width) {
  GridGeometry<Dim> b = g;
  for (int d = 0; d < Dim; ++d) {
    const int first = box.lo[d] * GridGeometry<Dim>::tile_width;
    const int end = std::min(box.hi[d] * GridGeometry<Dim>::tile_width + width - 1, g.nodes_along(d));
    b.offset[d] = first;
    b.box_nodes[d] = end - first;
  }
  return b;
}

/// The sums of one tile of a box at its footprint's nodes, for the owners of those nodes.
template <int Dim>
struct TileSums {
  int colour = 0;                      ///< the tile's colour (ScatterOrder::colour_of)
  IVec<Dim> first{};                   ///< global storage layer of the footprint's first node, per axis
  IVec<Dim> extent{};                  ///< node layers of the footprint inside the grid, per axis
  std::vector<GridNode<Dim>> records;  ///< extent^Dim records, axis 0 fastest
};

/// Whether local tile t of a box whose grid holds `tiles` tiles per axis lies at one of the box's faces: its
/// first tile, or its last (the grid's last tile holds only the layers above the box, unless the box ends at
/// the grid's last layer; either way the last two are kept).
template <int Dim>
bool face_tile(std::int32_t t, const IVec<Dim>& tiles) {
  for (int d = 0; d < Dim; ++d) {
    const int td = t % tiles[d];
    if (td == 0 || td >= tiles[d] - 2) return true;
    t /= tiles[d];
  }
  return false;
}

/// Keeps the sums of a box's face tiles during a P2G pass (the `keep` of p2g_add_keeping); tiles run in
/// parallel, each writes its own entry.
template <int Dim>
class FaceTileSums {
 public:
  FaceTileSums(const GridGeometry<Dim>& box, const ScatterOrder<Dim>& order)
      : box_(box), order_(&order), sums_(box.tile_count()) {}

  void operator()(std::int32_t t, const GridNode<Dim>* buffer) const {
    IVec<Dim> tiles, at;
    std::int32_t rest = t;
    for (int d = 0; d < Dim; ++d) {
      tiles[d] = box_.tiles_along(d);
      at[d] = rest % tiles[d];
      rest /= tiles[d];
    }
    if (!face_tile<Dim>(t, tiles)) return;
    const int F = order_->footprint();
    TileSums<Dim>& ts = sums_[static_cast<std::size_t>(t)];
    ts.colour = order_->colour_of(t);
    std::size_t count = 1;
    for (int d = 0; d < Dim; ++d) {
      ts.first[d] = at[d] * GridGeometry<Dim>::tile_width + box_.offset[d];
      ts.extent[d] = std::min(F, box_.nodes_along(d) - at[d] * GridGeometry<Dim>::tile_width);
      count *= static_cast<std::size_t>(ts.extent[d]);
    }
    ts.records.resize(count);
    IVec<Dim> i{};
    for (std::size_t k = 0; k < count; ++k) {
      std::size_t from = 0;
      for (int d = Dim - 1; d >= 0; --d)
        from = from * static_cast<std::size_t>(F) + static_cast<std::size_t>(i[d]);
      ts.records[k] = buffer[from];
      for (int d = 0; d < Dim; ++d) {
        if (++i[d] < ts.extent[d]) break;
        i[d] = 0;
      }
    }
  }

  /// The kept sums, by tile.
  std::vector<TileSums<Dim>> take() const {
    std::vector<TileSums<Dim>> out;
    for (TileSums<Dim>& ts : sums_)
      if (!ts.records.empty()) out.push_back(std::move(ts));
    return out;
  }

 private:
  GridGeometry<Dim> box_;
  const ScatterOrder<Dim>* order_;
  mutable std::vector<TileSums<Dim>> sums_;
};

/// The `keep` of an engine's P2G passes: the face tiles' sums of a divided grid, or nothing in one box.
/// Chosen at run time (one test per tile), so that each pass is compiled once rather than once per keep.
template <int Dim>
struct KeepFaceTiles {
  explicit KeepFaceTiles(const std::optional<FaceTileSums<Dim>>& kept) : sums(kept ? &*kept : nullptr) {}
  void operator()(std::int32_t t, const GridNode<Dim>* buffer) const {
    if (sums) (*sums)(t, buffer);
  }
  const FaceTileSums<Dim>* sums;
};

}  // namespace mpm

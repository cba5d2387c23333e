#pragma once
/// A deterministic, race-free order for particle-to-grid scatter that does not depend on how the grid is
/// divided between threads or ranks. The grid's tiles (GridGeometry::tile_width node layers per axis) are
/// coloured by the parities of their global tile coordinates, 2^Dim colours. A P2G pass sums the particles of
/// each tile, in id order, into a cleared buffer the size of the tile's footprint (its nodes and the width -
/// 1 layers above it, where its particles' stencils reach), small enough to stay in cache, and adds the
/// buffer into the grid; tiles of one colour have disjoint footprints, so they run in parallel, and the
/// colours go in order. A node lies in the footprint of at most one tile of each colour, so its value is
///     f_i = (((f_i^0 + P_i^{c_0}) + P_i^{c_1}) + ...),   P_i^c = the sum over the one tile of colour c,
/// a function of the grid and the particle ids alone: a rank that owns a set of whole tiles computes the same
/// P_i^c, and the halo adds them in the same colour order (docs/scaling.md).
#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/lanes.hpp"

namespace mpm {

template <int Dim>
class ScatterOrder {
 public:
  static constexpr int colours = 1 << Dim;

  ScatterOrder() = default;
  /// The tiles of grid g, for a kernel whose stencils are `width` nodes wide.
  ScatterOrder(const GridGeometry<Dim>& g, int width)
      : geometry_(g), footprint_(GridGeometry<Dim>::tile_width + width - 1) {
    for (int d = 0; d < Dim; ++d) tile_origin_[d] = g.offset[d] >> GridGeometry<Dim>::tile_shift;
    static_assert(GridGeometry<Dim>::tile_width >= 4, "footprints of tiles of one colour must not overlap");
    if (g.tile_count() > GridGeometry<Dim>::max_tiles)
      throw InputError(
          "grid: " + std::to_string(g.tile_count()) + " tiles of " +
          std::to_string(GridGeometry<Dim>::tile_width) + " node layers per axis, more than the " +
          std::to_string(GridGeometry<Dim>::max_tiles) + " one process can index; use fewer cells");
  }

  /// Sort the particles by field, then tile (`tile[p]`: flat tile index of particle p's stencil base node,
  /// StencilTiles), each tile's by id: a stable counting sort, then a sort by id of the runs whose particles
  /// were not stored in id order. `field[p]` < `fields` is the velocity field particle p projects to
  /// (contact, ParticleSet::field); each field's particles come out as one run, scattered by their own
  /// passes. The result is unique, so computing it in parallel gives the same order for any thread count.
  template <class Tiles>
  void build(const Tiles& tile, const std::vector<std::int64_t>& id, const std::vector<std::uint16_t>& field,
             int fields) {
    const int tiles = static_cast<int>(geometry_.tile_count());
    const int keys = tiles * fields;  // key = field * tiles + tile
    const auto key = [&](std::ptrdiff_t p) { return fields == 1 ? tile[p] : field[p] * tiles + tile[p]; };
    const auto n = static_cast<std::ptrdiff_t>(tile.size());
    const std::ptrdiff_t chunks =
        std::max<std::ptrdiff_t>(1, std::min<std::ptrdiff_t>(4 * num_threads(), n / 1024));
    const std::ptrdiff_t chunk = (n + chunks - 1) / chunks;
    count_.assign(static_cast<std::size_t>(chunks * keys), 0);
    parallel_for(
        chunks,
        [&](std::ptrdiff_t c) {
          std::int32_t* cnt = &count_[c * keys];
          for (std::ptrdiff_t p = c * chunk; p < std::min(n, (c + 1) * chunk); ++p) ++cnt[key(p)];
        },
        2);
    // Exclusive prefix over (key, chunk): chunk c's particles of key k start at count_[c*keys + k].
    tile_begin_.assign(keys + 1, 0);
    std::int32_t total = 0;
    for (int k = 0; k < keys; ++k) {
      tile_begin_[k] = total;
      for (std::ptrdiff_t c = 0; c < chunks; ++c) {
        const std::int32_t j = count_[c * keys + k];
        count_[c * keys + k] = total;
        total += j;
      }
    }
    tile_begin_[keys] = total;
    particles_ = n;
    order_.resize(tile.size());
    parallel_for(
        chunks,
        [&](std::ptrdiff_t c) {
          std::int32_t* cursor = &count_[c * keys];
          for (std::ptrdiff_t p = c * chunk; p < std::min(n, (c + 1) * chunk); ++p)
            order_[cursor[key(p)]++] = static_cast<std::int32_t>(p);
        },
        2);
    parallel_for(
        keys,
        [&](std::ptrdiff_t k) {
          const auto by_id = [&](std::int32_t a, std::int32_t b) { return id[a] < id[b]; };
          std::int32_t* first = order_.data() + tile_begin_[k];  // data(): a rank may hold no particles
          std::int32_t* last = order_.data() + tile_begin_[k + 1];
          if (!std::is_sorted(first, last, by_id)) std::sort(first, last, by_id);
        },
        particles_ >= 1024 ? 2 : PTRDIFF_MAX);
    identity_ = true;
    for (std::ptrdiff_t k = 0; k < n && identity_; ++k) identity_ = order_[k] == k;
    // Each field's tiles that hold particles, by colour, in flat-index order.
    colour_.resize(static_cast<std::size_t>(fields));
    for (int f = 0; f < fields; ++f) {
      for (auto& list : colour_[f]) list.clear();
      for (int t = 0; t < tiles; ++t)
        if (tile_begin_[f * tiles + t + 1] > tile_begin_[f * tiles + t])
          colour_[f][colour_of(t)].push_back(t);
    }
  }
  /// build for particles that all project to one field.
  template <class Tiles>
  void build(const Tiles& tile, const std::vector<std::int64_t>& id) {
    build(tile, id, {}, 1);
  }

  /// The velocity fields the particles were sorted by, and the storage range of field f's particles once they
  /// are stored in this order.
  int fields() const { return static_cast<int>(colour_.size()); }
  ParticleRange field_range(int f) const {
    const std::size_t tiles = geometry_.tile_count();
    return {tile_begin_[f * tiles], tile_begin_[(f + 1) * tiles]};
  }

  /// One P2G pass of field f's particles into `grid`: for each tile that holds some, call add(buffer,
  /// particles, count) for them in runs of at most `lanes`, each run adding its contributions to the node
  /// records of `buffer`, the tile's footprint (footprint^Dim records, axis 0 fastest, cleared); then show
  /// the tile's sums to keep(tile, buffer) and add the buffer into the grid's records. Tiles of one colour
  /// run in parallel (their footprints are disjoint), the colours one after the other.
  template <int lanes, class Add, class Keep>
  void scatter(Grid<Dim>& grid, Add&& add, Keep&& keep, int f = 0) const {
    std::size_t records = 1;
    for (int d = 0; d < Dim; ++d) records *= static_cast<std::size_t>(footprint_);
    const std::int32_t* begin = tile_begin_.data() + static_cast<std::size_t>(f) * geometry_.tile_count();
    for (const std::vector<std::int32_t>& tiles : colour_[f]) {
      parallel_for(
          static_cast<std::ptrdiff_t>(tiles.size()),
          [&](std::ptrdiff_t k) {
            // One buffer per thread, cleared once; each fold clears it again.
            static thread_local std::vector<GridNode<Dim>> buffer;
            if (buffer.size() < records) {
              buffer.resize(records);
              std::memset(static_cast<void*>(buffer.data()), 0, buffer.size() * sizeof(GridNode<Dim>));
            }
            const std::int32_t t = tiles[k];
            for (std::int32_t i = begin[t]; i < begin[t + 1]; i += lanes)
              add(&buffer[0].m, &order_[i], std::min(lanes, begin[t + 1] - i));
            keep(t, buffer.data());
            fold(t, buffer, grid);
          },
          particles_ >= 1024 ? 2 : PTRDIFF_MAX);
    }
  }

  /// The particles by tile and id (storage indices).
  const std::vector<std::int32_t>& order() const { return order_; }
  /// Whether the particles are stored in this order already.
  bool identity() const { return identity_; }
  /// The caller has reordered its particle arrays by order(): the order becomes the identity.
  void reordered() {
    for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<std::int32_t>(k);
    identity_ = true;
  }

  std::size_t bytes() const { return order_.capacity() * sizeof(std::int32_t); }

  /// Node layers per axis a tile's particles reach.
  int footprint() const { return footprint_; }
  /// Colour of tile t: the parities of its global tile coordinates, axis 0 in bit 0.
  int colour_of(std::int32_t t) const {
    int colour = 0;
    for (int d = 0; d < Dim; ++d) {
      colour |= ((t % geometry_.tiles_along(d) + tile_origin_[d]) & 1) << d;
      t /= geometry_.tiles_along(d);
    }
    return colour;
  }

 private:
  /// Add the footprint buffer of tile t into the grid's records and clear it.
  void fold(std::int32_t t, std::vector<GridNode<Dim>>& buffer, Grid<Dim>& grid) const {
    std::array<int, Dim> lo, hi;
    for (int d = 0; d < Dim; ++d) {
      lo[d] = t % geometry_.tiles_along(d) * GridGeometry<Dim>::tile_width;
      hi[d] = std::min(lo[d] + footprint_, geometry_.nodes_along(d));  // stencils reach no further
      t /= geometry_.tiles_along(d);
    }
    constexpr int R = static_cast<int>(sizeof(GridNode<Dim>) / sizeof(Real));
    const int row = (hi[0] - lo[0]) * R;
    std::array<int, Dim> i = lo;  // i[0] stays lo[0]: each visit is one row along axis 0
    while (true) {
      std::ptrdiff_t to_row = 0, from_row = 0;
      for (int d = Dim - 1; d >= 0; --d) {
        to_row = to_row * geometry_.nodes_along(d) + i[d];
        from_row = from_row * footprint_ + (i[d] - lo[d]);
      }
      Real* to = &grid.nodes[to_row].m;
      Real* from = &buffer[from_row].m;
      for (int k = 0; k < row; ++k) to[k] += from[k];
      std::memset(static_cast<void*>(from), 0, static_cast<std::size_t>(row) * sizeof(Real));
      int d = 1;
      for (; d < Dim; ++d) {
        if (++i[d] < hi[d]) break;
        i[d] = lo[d];
      }
      if (d == Dim) return;
    }
  }

  GridGeometry<Dim> geometry_;
  int footprint_ = 0;        ///< node layers per axis a tile's particles reach
  IVec<Dim> tile_origin_{};  ///< global tile coordinates of this box's first tile
  std::vector<std::int32_t> order_, tile_begin_, count_;
  std::vector<std::array<std::vector<std::int32_t>, colours>> colour_{1};  ///< per field
  std::ptrdiff_t particles_ = 0;
  bool identity_ = true;
};

}  // namespace mpm

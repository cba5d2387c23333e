#include "mpm/distributed/box_halo.hpp"

#include <algorithm>
#include <cstring>

#include "mpm/grid/grid.hpp"

namespace mpm {
namespace {

/// Call fn(i) for every index i with lo <= i < hi (per axis), axis 0 fastest; nothing when the range is
/// empty.
template <int Dim, class Fn>
void for_each_index(const IVec<Dim>& lo, const IVec<Dim>& hi, Fn&& fn) {
  for (int d = 0; d < Dim; ++d)
    if (hi[d] <= lo[d]) return;
  IVec<Dim> i = lo;
  while (true) {
    fn(i);
    int d = 0;
    for (; d < Dim; ++d) {
      if (++i[d] < hi[d]) break;
      i[d] = lo[d];
    }
    if (d == Dim) return;
  }
}

template <class T>
void append(std::vector<std::byte>& bytes, const T* from, std::size_t count) {
  const auto* b = reinterpret_cast<const std::byte*>(from);
  bytes.insert(bytes.end(), b, b + count * sizeof(T));
}

/// One kept tile sum at one node: the node (local flat index), the tile's colour, the record.
template <int Dim>
struct Part {
  std::int64_t node;
  int colour;
  const GridNode<Dim>* record;
};

/// Sums a message carries, one after the other: header (colour, first and end layer per axis, as int32), then
/// the records of the nodes [first, end) of the footprint, axis 0 fastest.
struct Header {
  std::int32_t colour, first[3], end[3];
};

}  // namespace

template <int Dim>
BoxHalo<Dim>::BoxHalo(const GridGeometry<Dim>& whole, std::vector<TileBox<Dim>> boxes, int rank, int width)
    : whole_(whole),
      box_(box_geometry(whole, boxes[static_cast<std::size_t>(rank)], width)),
      boxes_(std::move(boxes)),
      rank_(rank) {
  IVec<Dim> tiles;
  for (int d = 0; d < Dim; ++d) tiles[d] = whole.tiles_along(d);
  const TileBox<Dim>& mine = boxes_[static_cast<std::size_t>(rank)];
  for (int d = 0; d < Dim; ++d) {  // node index = storage layer - ghost
    const int first = mine.lo[d] * GridGeometry<Dim>::tile_width - whole.ghost;
    const int end = mine.hi[d] * GridGeometry<Dim>::tile_width - whole.ghost;
    inner_lo_[d] = whole.lo[d] + whole.h * (first + 3);
    inner_hi_[d] = whole.lo[d] + whole.h * (end - 1);
  }
  owner_.assign(whole.tile_count(), -1);
  for (std::size_t b = 0; b < boxes_.size(); ++b) {
    const GridGeometry<Dim> g = box_geometry(whole, boxes_[b], width);
    IVec<Dim> end;
    for (int d = 0; d < Dim; ++d) end[d] = g.offset[d] + g.nodes_along(d);
    first_.push_back(g.offset);
    end_.push_back(end);
    for_each_index<Dim>(boxes_[b].lo, boxes_[b].hi, [&](const IVec<Dim>& t) {
      std::int64_t flat = 0;
      for (int d = Dim - 1; d >= 0; --d) flat = flat * tiles[d] + t[d];
      owner_[static_cast<std::size_t>(flat)] = static_cast<std::int32_t>(b);
    });
  }
  for (std::size_t b = 0; b < boxes_.size(); ++b) {
    bool overlap = static_cast<int>(b) != rank;
    for (int d = 0; d < Dim; ++d)
      overlap = overlap && first_[b][d] < end_[static_cast<std::size_t>(rank)][d] &&
                first_[static_cast<std::size_t>(rank)][d] < end_[b][d];
    if (overlap) peers_.push_back(static_cast<int>(b));
  }
}

template <int Dim>
void BoxHalo<Dim>::sum(Grid<Dim>& grid, std::vector<TileSums<Dim>> kept, bool mass_momentum, bool force,
                       const Communicator& comm, const std::vector<Vec<Dim>>* force_base,
                       bool volume_gradient) const {
  const GridGeometry<Dim>& g = grid.geometry;
  const auto local = [&](const IVec<Dim>& s) {
    std::int64_t f = 0;
    for (int d = Dim - 1; d >= 0; --d) f = f * g.nodes_along(d) + (s[d] - g.offset[d]);
    return f;
  };
  // To every peer, the part of each kept footprint inside its grid.
  std::vector<std::vector<std::byte>> to(peers_.size());
  for (const TileSums<Dim>& ts : kept)
    for (std::size_t k = 0; k < peers_.size(); ++k) {
      const auto b = static_cast<std::size_t>(peers_[k]);
      Header h{ts.colour, {}, {}};
      bool empty = false;
      for (int d = 0; d < Dim; ++d) {
        h.first[d] = std::max(ts.first[d], first_[b][d]);
        h.end[d] = std::min(ts.first[d] + ts.extent[d], end_[b][d]);
        empty = empty || h.end[d] <= h.first[d];
      }
      if (empty) continue;
      append(to[k], &h, 1);
      IVec<Dim> lo, hi;
      for (int d = 0; d < Dim; ++d) lo[d] = h.first[d], hi[d] = h.end[d];
      for_each_index<Dim>(lo, hi, [&](const IVec<Dim>& s) {
        std::size_t r = 0;
        for (int d = Dim - 1; d >= 0; --d)
          r = r * static_cast<std::size_t>(ts.extent[d]) + static_cast<std::size_t>(s[d] - ts.first[d]);
        append(to[k], &ts.records[r], 1);
      });
    }
  const std::vector<std::vector<std::byte>> from = comm.exchange_with(peers_, to);
  // The sums other boxes sent, by node; the received records are copied out aligned.
  std::vector<GridNode<Dim>> received;
  std::vector<std::pair<std::int64_t, int>> foreign;  // (node, colour) per received record
  for (const std::vector<std::byte>& bytes : from)
    for (std::size_t at = 0; at < bytes.size();) {
      Header h;
      std::memcpy(&h, &bytes[at], sizeof h);
      at += sizeof h;
      IVec<Dim> lo, hi;
      for (int d = 0; d < Dim; ++d) lo[d] = h.first[d], hi[d] = h.end[d];
      for_each_index<Dim>(lo, hi, [&](const IVec<Dim>& s) {
        received.emplace_back();
        std::memcpy(static_cast<void*>(&received.back()), &bytes[at], sizeof(GridNode<Dim>));
        at += sizeof(GridNode<Dim>);
        foreign.emplace_back(local(s), h.colour);
      });
    }
  if (received.empty()) return;
  std::vector<Part<Dim>> parts;
  for (std::size_t k = 0; k < received.size(); ++k)
    parts.push_back({foreign[k].first, foreign[k].second, &received[k]});
  std::vector<std::int64_t> shared;
  for (const auto& [node, colour] : foreign) shared.push_back(node);
  std::sort(shared.begin(), shared.end());
  shared.erase(std::unique(shared.begin(), shared.end()), shared.end());
  // This box's own sums at those nodes.
  for (const TileSums<Dim>& ts : kept) {
    IVec<Dim> lo = ts.first, hi;
    for (int d = 0; d < Dim; ++d) hi[d] = ts.first[d] + ts.extent[d];
    std::size_t k = 0;
    for_each_index<Dim>(lo, hi, [&](const IVec<Dim>& s) {
      const std::int64_t node = local(s);
      if (std::binary_search(shared.begin(), shared.end(), node))
        parts.push_back({node, ts.colour, &ts.records[k]});
      ++k;
    });
  }
  // Each shared node: its fields of this pass from zero (or the force base), plus every tile's sum in colour
  // order (one tile per colour reaches a node).
  std::sort(parts.begin(), parts.end(), [](const Part<Dim>& a, const Part<Dim>& b) {
    return a.node != b.node ? a.node < b.node : a.colour < b.colour;
  });
  using S = NodeSlots<Dim>;
  const auto add = [&](std::int64_t at, const GridNode<Dim>* part, bool first) {
    Real* t = &grid.nodes[static_cast<std::size_t>(at)].m;
    const Real* f = &part->m;
    const auto field = [&](int slot, int count, const Real* base) {
      for (int c = 0; c < count; ++c)
        t[slot + c] = (first ? (base ? base[c] : Real(0)) : t[slot + c]) + f[slot + c];
    };
    if (mass_momentum) field(S::m, 1, nullptr), field(S::v, Dim, nullptr);
    if (volume_gradient) field(S::v_new, Dim, nullptr);
    if (force) field(S::a, Dim, force_base ? (*force_base)[static_cast<std::size_t>(at)].data() : nullptr);
  };
  for (std::size_t k = 0; k < parts.size(); ++k)
    add(parts[k].node, parts[k].record, k == 0 || parts[k - 1].node != parts[k].node);
}

template class BoxHalo<1>;
template class BoxHalo<2>;
template class BoxHalo<3>;

}  // namespace mpm

#include "mpm/distributed/decomposition.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "mpm/core/errors.hpp"

namespace mpm {
namespace {

/// Call fn(t, flat index) for every tile of box b of a grid with `tiles` tiles per axis, axis 0 fastest.
template <int Dim, class Fn>
void for_each_tile(const IVec<Dim>& tiles, const TileBox<Dim>& b, Fn&& fn) {
  if (b.tile_count() <= 0) return;
  IVec<Dim> t = b.lo;
  while (true) {
    std::int64_t flat = 0;
    for (int d = Dim - 1; d >= 0; --d) flat = flat * tiles[d] + t[d];
    fn(t, flat);
    int d = 0;
    for (; d < Dim; ++d) {
      if (++t[d] < b.hi[d]) break;
      t[d] = b.lo[d];
    }
    if (d == Dim) return;
  }
}

template <int Dim>
std::int64_t weight_of(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight,
                       const TileBox<Dim>& b) {
  std::int64_t w = 0;
  for_each_tile<Dim>(tiles, b, [&](const IVec<Dim>&, std::int64_t flat) { w += weight[flat]; });
  return w;
}

template <int Dim>
void bisect_into(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight, const IVec<Dim>& cut_limit,
                 const TileBox<Dim>& box, int ranks, std::vector<TileBox<Dim>>& out) {
  if (ranks == 1) {
    out.push_back(box);
    return;
  }
  // The longest axis that can be cut: cuts after layers 1 .. last_cut of the box.
  int axis = -1;
  const auto last_cut = [&](int d) { return std::min(box.hi[d] - box.lo[d] - 1, cut_limit[d] - box.lo[d]); };
  for (int d = 0; d < Dim; ++d)
    if (last_cut(d) >= 1 && (axis < 0 || box.hi[d] - box.lo[d] > box.hi[axis] - box.lo[axis])) axis = d;
  if (axis < 0)
    throw InputError(
        "cannot divide the grid between " + std::to_string(ranks) +
        " more ranks: a box is one tile (8 node layers) along every axis it can be cut across; run on "
        "fewer ranks");
  const int length = box.hi[axis] - box.lo[axis];
  // The weight of each tile layer across the axis.
  std::vector<std::int64_t> layer(static_cast<std::size_t>(length), 0);
  for_each_tile<Dim>(tiles, box, [&](const IVec<Dim>& t, std::int64_t flat) {
    layer[t[axis] - box.lo[axis]] += weight[flat];
  });
  std::int64_t total = 0;
  for (std::int64_t w : layer) total += w;
  const int low_ranks = ranks / 2;
  // Cut after layer c (1 <= c < length): the low side's weight times ranks against the total times low_ranks.
  int best = 1;
  std::int64_t best_miss = -1, below = 0;
  double best_gap = 0;
  const double proportional = static_cast<double>(length) * low_ranks / ranks;
  for (int c = 1; c <= last_cut(axis); ++c) {
    below += layer[c - 1];
    const std::int64_t miss = std::llabs(below * ranks - total * low_ranks);
    const double gap = std::abs(c - proportional);
    if (best_miss < 0 || miss < best_miss || (miss == best_miss && gap < best_gap)) {
      best = c;
      best_miss = miss;
      best_gap = gap;
    }
  }
  TileBox<Dim> low = box, high = box;
  low.hi[axis] = box.lo[axis] + best;
  high.lo[axis] = box.lo[axis] + best;
  bisect_into<Dim>(tiles, weight, cut_limit, low, low_ranks, out);
  bisect_into<Dim>(tiles, weight, cut_limit, high, ranks - low_ranks, out);
}

}  // namespace

template <int Dim>
std::vector<TileBox<Dim>> bisect(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight, int ranks,
                                 const IVec<Dim>& cut_limit) {
  TileBox<Dim> all;
  all.hi = tiles;
  if (ranks < 1) throw InputError("ranks: expected at least 1, got " + std::to_string(ranks));
  if (static_cast<std::int64_t>(weight.size()) != all.tile_count())
    throw InputError("decomposition: " + std::to_string(weight.size()) + " tile weights for " +
                     std::to_string(all.tile_count()) + " tiles");
  std::vector<TileBox<Dim>> out;
  out.reserve(static_cast<std::size_t>(ranks));
  bisect_into<Dim>(tiles, weight, cut_limit, all, ranks, out);
  return out;
}

template <int Dim>
double imbalance(const IVec<Dim>& tiles, const std::vector<std::int64_t>& weight,
                 const std::vector<TileBox<Dim>>& boxes) {
  std::int64_t total = 0, largest = 0;
  for (const TileBox<Dim>& b : boxes) {
    const std::int64_t w = weight_of<Dim>(tiles, weight, b);
    total += w;
    largest = std::max(largest, w);
  }
  if (total == 0) return 1;
  return static_cast<double>(largest) * static_cast<double>(boxes.size()) / static_cast<double>(total);
}

template std::vector<TileBox<1>> bisect<1>(const IVec<1>&, const std::vector<std::int64_t>&, int,
                                           const IVec<1>&);
template std::vector<TileBox<2>> bisect<2>(const IVec<2>&, const std::vector<std::int64_t>&, int,
                                           const IVec<2>&);
template std::vector<TileBox<3>> bisect<3>(const IVec<3>&, const std::vector<std::int64_t>&, int,
                                           const IVec<3>&);
template double imbalance<1>(const IVec<1>&, const std::vector<std::int64_t>&,
                             const std::vector<TileBox<1>>&);
template double imbalance<2>(const IVec<2>&, const std::vector<std::int64_t>&,
                             const std::vector<TileBox<2>>&);
template double imbalance<3>(const IVec<3>&, const std::vector<std::int64_t>&,
                             const std::vector<TileBox<3>>&);

}  // namespace mpm

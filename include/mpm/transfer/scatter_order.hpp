#pragma once
/// A deterministic, race-free order for particle-to-grid scatter. Particles are counting-sorted (stably)
/// into strips of `width` node layers along the slowest grid axis; strips of equal parity touch disjoint
/// nodes, so even strips run in parallel, then odd ones. Each node then receives its contributions in the
/// same order whatever the thread count.
#include <cstdint>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/shape/stencil.hpp"

namespace mpm {

class ScatterOrder {
 public:
  template <int Dim, int N>
  void build(const std::vector<Stencil<Dim, N>>& stencils, const GridGeometry<Dim>& g) {
    const auto slow = static_cast<std::int32_t>(g.stride(Dim - 1));
    const int strips = (g.nodes_along(Dim - 1) + N - 1) / N;
    strip_begin_.assign(strips + 1, 0);
    key_.resize(stencils.size());
    parallel_for(static_cast<std::ptrdiff_t>(stencils.size()),
                 [&](std::ptrdiff_t p) { key_[p] = stencils[p].node / slow / N; });
    for (std::int32_t k : key_) ++strip_begin_[k + 1];
    for (int s = 0; s < strips; ++s) strip_begin_[s + 1] += strip_begin_[s];
    order_.resize(stencils.size());
    cursor_.assign(strip_begin_.begin(), strip_begin_.end() - 1);
    for (std::size_t p = 0; p < key_.size(); ++p) order_[cursor_[key_[p]]++] = static_cast<std::int32_t>(p);
  }

  /// Call fn(p) for every particle: even strips in parallel, then odd strips in parallel.
  template <class Fn>
  void for_each(Fn&& fn) const {
    const int strips = static_cast<int>(strip_begin_.size()) - 1;
    for (int parity = 0; parity < 2; ++parity)
      parallel_for((strips - parity + 1) / 2, [&](std::ptrdiff_t k) {
        const int s = static_cast<int>(2 * k + parity);
        for (std::int32_t i = strip_begin_[s]; i < strip_begin_[s + 1]; ++i) fn(order_[i]);
      });
  }

  std::size_t bytes() const { return (key_.capacity() + order_.capacity()) * sizeof(std::int32_t); }

 private:
  std::vector<std::int32_t> key_, order_, strip_begin_, cursor_;
};

}  // namespace mpm

#pragma once
/// A deterministic, race-free order for particle-to-grid scatter. Particles are counting-sorted (stably)
/// into strips of `width` node layers along the slowest grid axis; strips of equal parity touch disjoint
/// nodes, so even strips run in parallel, then odd ones. Each node then receives its contributions in the
/// same order whatever the thread count.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"

namespace mpm {

class ScatterOrder {
 public:
  /// Strip of a stencil whose base node has storage index `base` (ghosts included) along the slowest axis.
  template <int N>
  static std::int32_t strip_of(std::int32_t base) {
    return base / N;
  }
  template <int Dim, int N>
  static int strip_count(const GridGeometry<Dim>& g) {
    return (g.nodes_along(Dim - 1) + N - 1) / N;
  }

  /// Stable counting sort of particles by strip. The result is unique, so computing it in parallel chunks
  /// gives the same order for any thread count.
  void build(const std::vector<std::int32_t>& strip, int strips) {
    const auto n = static_cast<std::ptrdiff_t>(strip.size());
    const std::ptrdiff_t chunks =
        std::max<std::ptrdiff_t>(1, std::min<std::ptrdiff_t>(4 * num_threads(), n / 1024));
    const std::ptrdiff_t chunk = (n + chunks - 1) / chunks;
    count_.assign(static_cast<std::size_t>(chunks * strips), 0);
    parallel_for(
        chunks,
        [&](std::ptrdiff_t c) {
          std::int32_t* cnt = &count_[c * strips];
          for (std::ptrdiff_t p = c * chunk; p < std::min(n, (c + 1) * chunk); ++p) ++cnt[strip[p]];
        },
        2);
    // Exclusive prefix over (strip, chunk): chunk c's particles of strip s start at count_[c*strips + s].
    strip_begin_.assign(strips + 1, 0);
    std::int32_t total = 0;
    for (int s = 0; s < strips; ++s) {
      strip_begin_[s] = total;
      for (std::ptrdiff_t c = 0; c < chunks; ++c) {
        const std::int32_t k = count_[c * strips + s];
        count_[c * strips + s] = total;
        total += k;
      }
    }
    strip_begin_[strips] = total;
    particles_ = n;
    order_.resize(strip.size());
    parallel_for(
        chunks,
        [&](std::ptrdiff_t c) {
          std::int32_t* cursor = &count_[c * strips];
          for (std::ptrdiff_t p = c * chunk; p < std::min(n, (c + 1) * chunk); ++p)
            order_[cursor[strip[p]]++] = static_cast<std::int32_t>(p);
        },
        2);
  }

  /// Call fn(p) for every particle: even strips in parallel, then odd strips in parallel.
  template <class Fn>
  void for_each(Fn&& fn) const {
    for_each_block<1>([&](const std::int32_t* particle, int) { fn(*particle); });
  }

  /// Call fn(particles, count) for the particles in scatter order, in runs of at most `lanes` of one strip:
  /// even strips in parallel, then odd strips in parallel.
  template <int lanes, class Fn>
  void for_each_block(Fn&& fn) const {
    const int strips = static_cast<int>(strip_begin_.size()) - 1;
    for (int parity = 0; parity < 2; ++parity)
      parallel_for((strips - parity + 1) / 2,
                   [&](std::ptrdiff_t k) {
                     const int s = static_cast<int>(2 * k + parity);
                     for (std::int32_t i = strip_begin_[s]; i < strip_begin_[s + 1]; i += lanes)
                       fn(&order_[i], std::min(lanes, strip_begin_[s + 1] - i));
                   },
                   particles_ >= 1024 ? 2 : strips);
  }

  std::size_t bytes() const { return order_.capacity() * sizeof(std::int32_t); }

 private:
  std::vector<std::int32_t> order_, strip_begin_, count_;
  std::ptrdiff_t particles_ = 0;
};

}  // namespace mpm

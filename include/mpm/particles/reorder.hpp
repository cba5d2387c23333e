#pragma once
/// Reordering per-particle arrays: new entry k is old entry order[k].
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// The scratch every array of a reorder goes through: one column of `column` bytes per particle, kept for
/// later reorders, so that a reorder holds 8 bytes per particle whatever the records it moves.
class ReorderBuffer {
 public:
  static constexpr std::size_t column = sizeof(double);
  /// Room for `bytes` bytes, 64-byte aligned; what it held is lost when it grows.
  std::byte* room(std::size_t bytes) {
    const std::size_t lines = (bytes + sizeof(Line) - 1) / sizeof(Line);
    if (lines_.size() < lines) {
      lines_ =
          std::vector<Line>();  // freed first, so that the old and the new buffer are never held together
      lines_.resize(lines);
    }
    return lines_.data()->bytes;
  }
  std::size_t bytes() const { return lines_.capacity() * sizeof(Line); }

 private:
  struct alignas(64) Line {
    std::byte bytes[64];
  };
  std::vector<Line> lines_;
};

/// a[k] = a_old[order[k]] for an array of order.size() entries; arrays of another size (unused, empty) are
/// left as they are. Each record is moved a column of ReorderBuffer::column bytes at a time: the column of
/// every record is gathered into `buffer`, then copied back (every per-particle record is made of plain
/// numbers, and the columns of a record are independent bytes).
template <class T>
void gather_by(std::vector<T>& a, const std::vector<std::int32_t>& order, ReorderBuffer& buffer) {
  if (a.size() != order.size()) return;
  constexpr std::size_t column = ReorderBuffer::column;
  constexpr std::size_t last = sizeof(T) % column == 0 ? column : sizeof(T) % column;
  const auto n = static_cast<std::ptrdiff_t>(a.size());
  std::byte* kept = buffer.room(a.size() * column);
  std::byte* to = reinterpret_cast<std::byte*>(a.data());
  for (std::size_t at = 0; at < sizeof(T); at += column) {
    const auto move = [&](std::byte* into, const std::byte* from) {
      if (at + column <= sizeof(T))
        std::memcpy(into, from, column);
      else
        std::memcpy(into, from, last);
    };
    parallel_for(n, [&](std::ptrdiff_t k) { move(kept + k * column, to + order[k] * sizeof(T) + at); });
    parallel_for(n, [&](std::ptrdiff_t k) { move(to + k * sizeof(T) + at, kept + k * column); });
  }
}

/// Reorder every array of p, its material state and the arrays `more` by `order`, through `buffer`.
template <int Dim, class... More>
void reorder_particles(ParticleSet<Dim>& p, const std::vector<std::int32_t>& order, ReorderBuffer& buffer,
                       std::vector<More>&... more) {
  p.for_each_array([&](auto& a) { gather_by(a, order, buffer); });
  (gather_by(more, order, buffer), ...);
}

}  // namespace mpm

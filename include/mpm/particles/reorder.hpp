#pragma once
/// Reordering per-particle arrays: new entry k is old entry order[k].
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// The scratch every array of a reorder goes through: one buffer, sized for the largest element type moved and
/// kept for later reorders, so that repeated reorders neither allocate nor hold a copy of each array.
class ReorderBuffer {
 public:
  /// Room for `bytes` bytes, 64-byte aligned; what it held is lost when it grows.
  std::byte* room(std::size_t bytes) {
    const std::size_t lines = (bytes + sizeof(Line) - 1) / sizeof(Line);
    if (lines_.size() < lines) {
      lines_ = std::vector<Line>();  // freed first, so that the old and the new buffer are never held together
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

/// a[k] = a_old[order[k]] for an array of order.size() entries; arrays of another size (unused, empty) are left
/// as they are. The records are copied as bytes into `buffer` and back (every per-particle record is made of plain
/// numbers).
template <class T>
void gather_by(std::vector<T>& a, const std::vector<std::int32_t>& order, ReorderBuffer& buffer) {
  if (a.size() != order.size()) return;
  const auto n = static_cast<std::ptrdiff_t>(a.size());
  std::byte* kept = buffer.room(a.size() * sizeof(T));
  std::byte* to = reinterpret_cast<std::byte*>(a.data());
  parallel_for(n, [&](std::ptrdiff_t k) { std::memcpy(kept + k * sizeof(T), to + order[k] * sizeof(T), sizeof(T)); });
  parallel_for(n, [&](std::ptrdiff_t k) { std::memcpy(to + k * sizeof(T), kept + k * sizeof(T), sizeof(T)); });
}

/// Reorder every array of p and its material state through `buffer`, grown once to the largest array.
template <int Dim>
void reorder_particles(ParticleSet<Dim>& p, const std::vector<std::int32_t>& order, ReorderBuffer& buffer) {
  std::size_t largest = 0;
  p.for_each_array([&](auto& a) {
    if (a.size() == order.size()) largest = std::max(largest, a.size() * sizeof(a[0]));
  });
  buffer.room(largest);
  p.for_each_array([&](auto& a) { gather_by(a, order, buffer); });
}

}  // namespace mpm

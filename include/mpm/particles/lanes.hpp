#pragma once
/// Blocks of `simd::lanes` consecutive particles, whose fields are read and written in SIMD lanes so that a
/// loop over particles evaluates several per instruction. Blocks are fixed by particle index (block b holds
/// particles b*lanes ...), so results do not depend on the thread count.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "mpm/core/simd.hpp"

namespace mpm {

using simd::IntLanes;
using simd::RealLanes;

/// Number of Reals in a per-particle record (a Vec, Mat, SymTensor, stencil ... made only of Reals).
template <class Record>
inline constexpr int reals_in = static_cast<int>(sizeof(Record) / sizeof(Real));

/// Lanes of a record's members: member c of the record of lane k in lane k of element c.
template <class Record>
using RecordLanes = std::array<RealLanes, reals_in<Record>>;

/// Particles [begin, end) of the arrays: those of one velocity field (ScatterOrder::field_range), or all.
struct ParticleRange {
  std::ptrdiff_t begin, end;
  std::ptrdiff_t size() const { return end - begin; }
};

/// SIMD lanes of particles: the particles of block b of the particle arrays, or up to `lanes` listed ones.
/// Lanes past the last particle repeat it (they are read, never written).
struct LaneBlock {
  static constexpr int width = simd::lanes;
  std::ptrdiff_t first;  ///< index of the first particle
  int active;            ///< lanes holding distinct particles, the first ones
  bool contiguous;       ///< lane k holds particle first + k, for every lane
  IntLanes index;        ///< particle index of each lane

  LaneBlock(std::ptrdiff_t b, std::ptrdiff_t n) : LaneBlock(b, ParticleRange{0, n}) {}
  /// Block b of the particles of `range`, counted from its first.
  LaneBlock(std::ptrdiff_t b, ParticleRange range) : first(range.begin + b * width) {
    active = static_cast<int>(std::min<std::ptrdiff_t>(width, range.end - first));
    contiguous = active == width;
    for (int k = 0; k < width; ++k) index[k] = std::min<std::ptrdiff_t>(first + k, range.end - 1);
  }
  LaneBlock(const std::int32_t* particles, int count) : first(particles[0]), active(count), contiguous(true) {
    for (int k = 0; k < width; ++k) {
      index[k] = particles[std::min(k, count - 1)];
      contiguous = contiguous && index[k] == first + k;
    }
  }
  static std::ptrdiff_t count(std::size_t n) { return (static_cast<std::ptrdiff_t>(n) + width - 1) / width; }
  static std::ptrdiff_t count(ParticleRange r) { return (r.size() + width - 1) / width; }

  /// The records f[i] of the block's particles, member by member.
  template <class Record>
  [[gnu::always_inline]] RecordLanes<Record> load(const std::vector<Record>& f) const {
    constexpr int R = reals_in<Record>;
    static_assert(sizeof(Record) == R * sizeof(Real), "records must be made of Reals");
    const Real* base = reinterpret_cast<const Real*>(f.data());
    if (contiguous) return simd::load_records<R>(base + first * R);
    RecordLanes<Record> m;
    for (int c = 0; c < R; ++c) m[c] = simd::gather(base + c, index * R);
    return m;
  }
  /// Member c of the records f[i] of the block's particles (a gather, where load would read whole records).
  template <class Record>
  [[gnu::always_inline]] RealLanes load_member(const std::vector<Record>& f, int c) const {
    return simd::gather(reinterpret_cast<const Real*>(f.data()) + c, index * reals_in<Record>);
  }
  /// The 16-bit indices f[i] (material indices) of the block's particles.
  [[gnu::always_inline]] IntLanes load_indices(const std::vector<std::uint16_t>& f) const {
    using Loaded = std::uint16_t __attribute__((vector_size(sizeof(std::uint16_t) * width)));
    if (contiguous) {
      Loaded v;
      std::memcpy(&v, f.data() + first, sizeof(v));
      return __builtin_convertvector(v, IntLanes);
    }
    IntLanes m;
    for (int k = 0; k < width; ++k) m[k] = f[index[k]];
    return m;
  }
  /// Store the records of the active lanes.
  template <class Record>
  [[gnu::always_inline]] void store(std::vector<Record>& f, const RecordLanes<Record>& m) const {
    constexpr int R = reals_in<Record>;
    Real* base = reinterpret_cast<Real*>(f.data());
    if (contiguous) return simd::store_records<R>(base + first * R, m);
    for (int c = 0; c < R; ++c) simd::scatter(base + c, index * R, m[c], active);
  }
};

}  // namespace mpm

#pragma once
/// A minimal portable SIMD layer on GCC vector extensions: one register of doubles (`RealLanes`), the
/// 64-bit integers of the same width (`IntLanes`, also the type of lane comparisons: -1 true, 0 false), and a
/// branch-free natural logarithm on them.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "mpm/core/types.hpp"

#if defined(__AVX__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace mpm::simd {

/// Doubles per register of the target ISA: 8 with AVX-512, 4 with AVX, else 2 (SSE2, the x86-64 baseline).
#if defined(__AVX512F__)
inline constexpr int lanes = 8;
#elif defined(__AVX__)
inline constexpr int lanes = 4;
#else
inline constexpr int lanes = 2;
#endif

using RealLanes = Real __attribute__((vector_size(8 * lanes)));
using IntLanes = std::int64_t __attribute__((vector_size(8 * lanes)));

/// The result of comparing RealLanes: -1 (all bits set) where true, 0 where false.
using MaskLanes = IntLanes;

/// What comparing two T gives: bool for one value, MaskLanes for lanes.
template <class T>
using MaskOf = decltype(T{} < T{});

/// True when every lane of m is true.
inline bool all(const MaskLanes& m) {
  std::int64_t every = -1;
  for (int k = 0; k < lanes; ++k) every &= m[k];
  return every != 0;
}

/// True when some lane of m is true.
inline bool any(const MaskLanes& m) {
  std::int64_t some = 0;
  for (int k = 0; k < lanes; ++k) some |= m[k];
  return some != 0;
}

/// All lanes equal to v.
inline RealLanes broadcast(Real v) {
  return RealLanes{} + v;
}

/// Lane k of the result is base[offset[k]] (a hardware gather where the ISA has one).
[[gnu::always_inline]] inline RealLanes gather(const Real* base, const IntLanes& offset) {
  // The masked forms with a zero source: the plain intrinsics read an uninitialised register (GCC 12 warns).
#if defined(__AVX512F__)
  return reinterpret_cast<RealLanes>(
      _mm512_mask_i64gather_pd(_mm512_setzero_pd(), 0xff, reinterpret_cast<__m512i>(offset), base, 8));
#elif defined(__AVX2__)
  return reinterpret_cast<RealLanes>(
      _mm256_mask_i64gather_pd(_mm256_setzero_pd(), base, reinterpret_cast<__m256i>(offset),
                               _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), 8));
#else
  RealLanes v;
  for (int k = 0; k < lanes; ++k) v[k] = base[offset[k]];
  return v;
#endif
}

/// base[offset[k]] = v[k] for the first `active` lanes, in lane order.
[[gnu::always_inline]] inline void scatter(Real* base, const IntLanes& offset, const RealLanes& v,
                                           int active) {
#if defined(__AVX512F__)
  const auto mask = static_cast<__mmask8>((1u << active) - 1);
  _mm512_mask_i64scatter_pd(base, mask, reinterpret_cast<__m512i>(offset), reinterpret_cast<__m512d>(v), 8);
#else
  for (int k = 0; k < active; ++k) base[offset[k]] = v[k];
#endif
}

/// `lanes` consecutive records of R Reals each (records[k*R + c] is member c of record k), transposed into R
/// vectors: member c of record k in lane k of vector c. With AVX-512 the records are read with R contiguous
/// loads and rearranged in registers (two-source permutes), which measured faster than hardware gathers.
template <int R>
std::array<RealLanes, R> load_records(const Real* records);
/// The inverse of load_records: writes all R members of `lanes` consecutive records.
template <int R>
void store_records(Real* records, const std::array<RealLanes, R>& members);

#if defined(__AVX512F__)
namespace detail {
/// Permutation tables of the record transposition for 8 lanes. Source vectors are taken in pairs (2q, 2q+1);
/// index[t][q] gives, for each lane of target t, its element in that pair, and mask[t][q] the lanes it fills.
template <int R>
struct RecordTables {
  static constexpr int pairs = (R + 1) / 2;
  struct Table {
    std::int64_t index[R][pairs][8];
    unsigned mask[R][pairs];
  };
  // Load: target c (a member) lane k is element j = k R + c of the records, in source vector j / 8.
  static constexpr Table load = [] {
    Table t{};
    for (int c = 0; c < R; ++c)
      for (int k = 0; k < 8; ++k) {
        const int j = k * R + c, q = j / 16;
        t.index[c][q][k] = j - 16 * q;
        t.mask[c][q] |= 1u << k;
      }
    return t;
  }();
  // Store: target s (a block of 8 Reals) lane i is element e = 8 s + i, member e % R of record e / R.
  static constexpr Table store = [] {
    Table t{};
    for (int s = 0; s < R; ++s)
      for (int i = 0; i < 8; ++i) {
        const int e = 8 * s + i, c = e % R, q = c / 2;
        t.index[s][q][i] = (c % 2) * 8 + e / R;
        t.mask[s][q] |= 1u << i;
      }
    return t;
  }();
};

/// Targets from sources by the tables: target t = blend over pairs q of permute(source 2q, source 2q+1).
/// 8 x 8 transpose in three rounds of two-source shuffles (24 instructions).
[[gnu::always_inline]] inline std::array<RealLanes, 8> transpose8(const std::array<RealLanes, 8>& r) {
  __m512d t[8], u[8];
  for (int i = 0; i < 4; ++i) {
    const __m512d a = reinterpret_cast<__m512d>(r[2 * i]), b = reinterpret_cast<__m512d>(r[2 * i + 1]);
    t[2 * i] = _mm512_unpacklo_pd(a, b);  // a0 b0 a2 b2 a4 b4 a6 b6
    t[2 * i + 1] = _mm512_unpackhi_pd(a, b);
  }
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      u[4 * i + j] = _mm512_shuffle_f64x2(t[4 * i + j], t[4 * i + j + 2], 0x88);      // 128-bit lanes 0, 2
      u[4 * i + j + 2] = _mm512_shuffle_f64x2(t[4 * i + j], t[4 * i + j + 2], 0xdd);  // lanes 1, 3
    }
  std::array<RealLanes, 8> out;
  for (int c = 0; c < 4; ++c) {
    out[c] = reinterpret_cast<RealLanes>(_mm512_shuffle_f64x2(u[c], u[c + 4], 0x88));
    out[c + 4] = reinterpret_cast<RealLanes>(_mm512_shuffle_f64x2(u[c], u[c + 4], 0xdd));
  }
  return out;
}

template <int R>
[[gnu::always_inline]] inline std::array<RealLanes, R> permute_records(
    const std::array<RealLanes, R>& source, const typename RecordTables<R>::Table& table) {
  if constexpr (R == 8) return transpose8(source);  // both directions are the transpose
  std::array<RealLanes, R> target;
  for (int t = 0; t < R; ++t) {
    __m512d r = _mm512_setzero_pd();
    for (int q = 0; q < RecordTables<R>::pairs; ++q) {
      if (!table.mask[t][q]) continue;
      const __m512i index = _mm512_loadu_si512(table.index[t][q]);
      const __m512d a = reinterpret_cast<__m512d>(source[2 * q]);
      const __m512d b = reinterpret_cast<__m512d>(source[std::min(2 * q + 1, R - 1)]);
      r = _mm512_mask_blend_pd(static_cast<__mmask8>(table.mask[t][q]), r,
                               _mm512_permutex2var_pd(a, index, b));
    }
    target[t] = reinterpret_cast<RealLanes>(r);
  }
  return target;
}
}  // namespace detail

template <int R>
[[gnu::always_inline]] inline std::array<RealLanes, R> load_records(const Real* records) {
  // Full-mask loads (and stores below): GCC turns a loop of plain ones into a copy through the stack in
  // 32-byte halves, whose 64-byte reloads miss store forwarding.
  std::array<RealLanes, R> source;
  for (int s = 0; s < R; ++s)
    source[s] = reinterpret_cast<RealLanes>(_mm512_maskz_loadu_pd(0xff, records + 8 * s));
  return detail::permute_records<R>(source, detail::RecordTables<R>::load);
}

template <int R>
[[gnu::always_inline]] inline void store_records(Real* records, const std::array<RealLanes, R>& members) {
  const std::array<RealLanes, R> blocks = detail::permute_records<R>(members, detail::RecordTables<R>::store);
  for (int s = 0; s < R; ++s)
    _mm512_mask_storeu_pd(records + 8 * s, 0xff, reinterpret_cast<__m512d>(blocks[s]));
}
#else
template <int R>
[[gnu::always_inline]] inline std::array<RealLanes, R> load_records(const Real* records) {
  std::array<RealLanes, R> members;
  for (int c = 0; c < R; ++c)
    for (int k = 0; k < lanes; ++k) members[c][k] = records[k * R + c];
  return members;
}

template <int R>
[[gnu::always_inline]] inline void store_records(Real* records, const std::array<RealLanes, R>& members) {
  for (int c = 0; c < R; ++c)
    for (int k = 0; k < lanes; ++k) records[k * R + c] = members[c][k];
}
#endif

/// Add the contributions of a block of particles to the nodes of their stencils, particle after particle:
/// records[(base[k] + offset[o]) * R + c] += members[o][c][k] for lane k = 0 .. active-1, c < W (the leading
/// W of a record's R Reals), and for each lane over its nodes o in order. A node thus receives its
/// contributions in the same order as from one particle at a time. Neighbouring lanes usually share nodes;
/// visiting all of one lane's (distinct) nodes before the next lane's keeps the read-add-write of a shared
/// node several instructions apart.
template <int R, std::size_t W, std::size_t Nodes>
[[gnu::always_inline]] inline void add_stencil_records(
    Real* records, const IntLanes& base, const std::array<std::int32_t, Nodes>& offset,
    const std::array<std::array<RealLanes, W>, Nodes>& members, int active) {
  static_assert(W <= R, "a record holds the members added to it");
#if defined(__AVX512F__)
  if constexpr (W == std::size_t{lanes}) {  // a record's leading W Reals per register
    std::array<std::array<RealLanes, W>, Nodes> by_record;
    for (std::size_t o = 0; o < Nodes; ++o) by_record[o] = detail::transpose8(members[o]);
    for (int k = 0; k < active; ++k)
      for (std::size_t o = 0; o < Nodes; ++o) {
        Real* record = records + (base[k] + offset[o]) * R;
        _mm512_storeu_pd(record,
                         _mm512_add_pd(_mm512_loadu_pd(record), reinterpret_cast<__m512d>(by_record[o][k])));
      }
    return;
  }
#endif
  // Records of other sizes: lane k of each member is read in place (a transposition costs more here).
  for (int k = 0; k < active; ++k)
    for (std::size_t o = 0; o < Nodes; ++o) {
      Real* record = records + (base[k] + offset[o]) * R;
      for (std::size_t c = 0; c < W; ++c) record[c] += members[o][c][k];
    }
}

/// floor(v) for v > -16, without a libm call on baseline x86-64. Grid coordinates of particles inside the
/// grid are >= -1. Rounding in v + 16 can only overshoot by one (just below an integer), which the comparison
/// corrects.
/// The scalar overload clamps a coordinate outside [-16, 2^30] (a particle far off the grid, or NaN, which
/// maps to 2^30) first, so that its conversion to int is defined. The lanes overload subtracts in unsigned
/// arithmetic, so that a non-finite lane (converted to INT64_MIN by the instruction) wraps instead of
/// overflowing; its index is never used, because the G2P pass that moved the particle reports it before the
/// next transfer.
inline constexpr Real floor_index_limit = 1 << 30;
inline int floor_index(Real v) {
  const Real c = v < floor_index_limit ? (v > -16 ? v : -16) : floor_index_limit;
  const int b = static_cast<int>(c + 16) - 16;
  return b - (c < b);
}
inline IntLanes floor_index(const RealLanes& v) {
  using Unsigned = std::uint64_t __attribute__((vector_size(sizeof(IntLanes))));
  const IntLanes b = (IntLanes)((Unsigned) __builtin_convertvector(v + 16, IntLanes) - 16);
  return b + (v < __builtin_convertvector(b, RealLanes));  // true is -1
}

/// An index as a Real, for one value or lanes.
inline Real to_real(int i) {
  return i;
}
inline RealLanes to_real(const IntLanes& i) {
  return __builtin_convertvector(i, RealLanes);
}

/// std::min and std::max, for one value or lanes (same comparisons, so the same results).
template <class T>
T min(const T& a, const T& b) {
  return b < a ? b : a;
}
template <class T>
T max(const T& a, const T& b) {
  return a < b ? b : a;
}
/// On lanes, the min and max instructions, one each rather than a comparison and a blend: min(a, b) is
/// minpd(b, a), b < a ? b : a, and max(a, b) maxpd(b, a), b > a ? b : a, the comparisons above, which give a
/// where either is NaN or both are zeros.
#if defined(__AVX512F__)
[[gnu::always_inline]] inline RealLanes min(const RealLanes& a, const RealLanes& b) {
  return reinterpret_cast<RealLanes>(
      _mm512_min_pd(reinterpret_cast<__m512d>(b), reinterpret_cast<__m512d>(a)));
}
[[gnu::always_inline]] inline RealLanes max(const RealLanes& a, const RealLanes& b) {
  return reinterpret_cast<RealLanes>(
      _mm512_max_pd(reinterpret_cast<__m512d>(b), reinterpret_cast<__m512d>(a)));
}
#elif defined(__AVX__)
[[gnu::always_inline]] inline RealLanes min(const RealLanes& a, const RealLanes& b) {
  return reinterpret_cast<RealLanes>(
      _mm256_min_pd(reinterpret_cast<__m256d>(b), reinterpret_cast<__m256d>(a)));
}
[[gnu::always_inline]] inline RealLanes max(const RealLanes& a, const RealLanes& b) {
  return reinterpret_cast<RealLanes>(
      _mm256_max_pd(reinterpret_cast<__m256d>(b), reinterpret_cast<__m256d>(a)));
}
#endif

/// The square root, for one value or lanes: IEEE's correctly rounded one either way, so the same bits.
inline Real sqrt(Real x) {
  return std::sqrt(x);
}
[[gnu::always_inline]] inline RealLanes sqrt(const RealLanes& x) {
#if defined(__AVX512F__)
  return reinterpret_cast<RealLanes>(_mm512_sqrt_pd(reinterpret_cast<__m512d>(x)));
#elif defined(__AVX__)
  return reinterpret_cast<RealLanes>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(x)));
#else
  RealLanes r;
  for (int k = 0; k < lanes; ++k) r[k] = std::sqrt(x[k]);
  return r;
#endif
}

/// |x| and copysign(x, y) through the sign bit, for one value or lanes.
inline Real abs(Real x) {
  return std::fabs(x);
}
inline Real copysign(Real x, Real y) {
  return std::copysign(x, y);
}
inline RealLanes abs(const RealLanes& x) {
  return reinterpret_cast<RealLanes>(reinterpret_cast<IntLanes>(x) &
                                     std::numeric_limits<std::int64_t>::max());
}
inline RealLanes copysign(const RealLanes& x, const RealLanes& y) {
  constexpr std::int64_t magnitude = std::numeric_limits<std::int64_t>::max();
  return reinterpret_cast<RealLanes>((reinterpret_cast<IntLanes>(x) & magnitude) |
                                     (reinterpret_cast<IntLanes>(y) & ~magnitude));
}

/// det F of a Dim x Dim matrix, for one value or lanes (cofactor expansion along the first column).
template <int Dim, class T>
T determinant(const T (&F)[Dim][Dim]) {
  if constexpr (Dim == 1)
    return F[0][0];
  else if constexpr (Dim == 2)
    return F[0][0] * F[1][1] - F[1][0] * F[0][1];
  else
    return F[0][0] * (F[1][1] * F[2][2] - F[2][1] * F[1][2]) -
           F[1][0] * (F[0][1] * F[2][2] - F[2][1] * F[0][2]) +
           F[2][0] * (F[0][1] * F[1][2] - F[1][1] * F[0][2]);
}

namespace detail {

using UIntLanes = std::uint64_t __attribute__((vector_size(8 * lanes)));

/// a*b rounded by itself: never fused with the addition that uses it into an FMA (GCC's default on FMA
/// targets), so the logarithm rounds alike on every ISA, in every lane width and in the scalar overload.
/// (Clang before version 15 lacks the barrier; with -ffp-contract=off, which the build sets, it never fuses.)
template <class V, class W>
V mul(V a, W b) {
#if __has_builtin(__builtin_assoc_barrier)
  return __builtin_assoc_barrier(a * b);
#else
  return a * b;
#endif
}

/// log(x) for V = Real (bits in U = uint64_t) or V = RealLanes (U = UIntLanes): the same IEEE operations in
/// the same order, hence the same bits. Algorithm of fdlibm e_log.c (Sun Microsystems 1993; FreeBSD msun
/// __ieee754_log) with its more accurate formula for every f (fdlibm branches on the size of f): error
/// < 1 ulp. Branch-free: special inputs go through the arithmetic and are replaced at the end.
template <class V, class U>
[[gnu::always_inline]] inline V log(V x) {
  // e_log.c constants: ln2 = ln2_hi + ln2_lo with k*ln2_hi exact for |k| < 2^11, and the minimax
  // coefficients of R(z) = Lg1 z + ... + Lg7 z^7 ~ (log((1+s)/(1-s)) - 2s)/s, z = s^2.
  constexpr Real ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
  constexpr Real Lg1 = 6.666666666666735130e-01, Lg2 = 3.999999999940941908e-01,
                 Lg3 = 2.857142874366239149e-01, Lg4 = 2.222219843214978396e-01,
                 Lg5 = 1.818357216161805012e-01, Lg6 = 1.531383769920937332e-01,
                 Lg7 = 1.479819860511658591e-01;
  // Subnormals (and x <= 0, replaced below) are scaled by 2^54 into the normal range.
  const auto tiny = x < 0x1p-1022;
  const U bits = std::bit_cast<U>(tiny ? x * 0x1p54 : x);
  // x = 2^k (1+f) with 1+f in [sqrt(2)/2, sqrt(2)): 1+f = 1.m from the mantissa m, halved when 1.m >=
  // sqrt(2), i.e. when the high 20 bits of m reach 0x6a09c (sqrt(2) = 0x3ff6a09e...), flagged by the carry
  // into bit 52 of m + 0x95f64 * 2^32 (0x95f64 = 0x100000 - 0x6a09c).
  const U m = bits & 0x000fffffffffffffu;
  const U half = (m + 0x00095f6400000000u) & 0x0010000000000000u;
  const V f = std::bit_cast<V>(m | (half ^ 0x3ff0000000000000u)) - 1.0;
  const U k = (bits >> 52) - 1023u + (half >> 52);
  // k as a double: 1.5*2^52 + k holds k in its low mantissa bits (exact for |k| < 2^51); minus 54 if scaled.
  const V dk = std::bit_cast<V>(k + 0x4338000000000000u) - (tiny ? 0x1.8p52 + 54 : 0x1.8p52);
  // log(1+f) = 2s + s R(s^2), s = f/(2+f); R from its even and odd powers of w = z^2.
  const V s = f / (2.0 + f);
  const V z = s * s;
  const V w = z * z;
  const V R = mul(z, Lg1 + mul(w, Lg3 + mul(w, Lg5 + mul(w, Lg7)))) + mul(w, Lg2 + mul(w, Lg4 + mul(w, Lg6)));
  // log(x) = k ln2 + f - (hfsq - s (hfsq + R)), hfsq = f^2/2, summed from the small terms up.
  const V hfsq = mul(0.5 * f, f);
  const V r = mul(dk, ln2_hi) - ((hfsq - (mul(s, hfsq + R) + mul(dk, ln2_lo))) - f);
  // Special inputs: +inf and NaN give x + x (+inf, NaN), x < 0 NaN, x = +-0 -inf.
  constexpr Real inf = std::numeric_limits<Real>::infinity(), nan = std::numeric_limits<Real>::quiet_NaN();
  return x == 0.0 ? -inf : x < 0.0 ? nan : x < inf ? r : x + x;
}

}  // namespace detail

/// Natural logarithm of every lane, < 1 ulp (see detail::log). log(+inf) = +inf, log(+-0) = -inf,
/// log(x < 0) = NaN, log(NaN) = NaN; subnormals to the same bound.
[[gnu::always_inline]] inline RealLanes log(RealLanes x) {
  return detail::log<RealLanes, detail::UIntLanes>(x);
}

/// Natural logarithm of one value: bit-for-bit the vector logarithm of a lane holding x (the algorithm
/// instantiated on Real, measured 1.3-1.9x faster than taking lane 0 of the vector version).
inline Real log(Real x) {
  return detail::log<Real, std::uint64_t>(x);
}

}  // namespace mpm::simd

// The SIMD layer (mpm/core/simd.hpp): lane count, and the fdlibm logarithm against glibc's std::log
// (correctly rounded to within ~0.5 ulp), its special values and subnormals, and the scalar overload
// returning the bits of the vector one in every lane.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include "mpm/core/simd.hpp"

namespace {

using mpm::Real;
using mpm::simd::lanes;
using mpm::simd::RealLanes;
constexpr Real kInf = std::numeric_limits<Real>::infinity();
constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr std::size_t kLanes = lanes;

/// Doubles mapped monotonically onto integers (-0 and +0 both to 0): consecutive doubles differ by 1.
std::int64_t ordered(Real x) {
  const auto i = std::bit_cast<std::int64_t>(x);
  return i < 0 ? std::numeric_limits<std::int64_t>::min() - i : i;
}

/// Distance in ulps between two finite doubles.
std::int64_t ulps(Real a, Real b) {
  return std::llabs(ordered(a) - ordered(b));
}

/// The vector logarithm of every x, lanes filled with consecutive entries (the last register padded with 1).
std::vector<Real> log_lanes(const std::vector<Real>& x) {
  std::vector<Real> out(x.size());
  for (std::size_t i = 0; i < x.size(); i += kLanes) {
    RealLanes v = mpm::simd::broadcast(1.0);
    for (std::size_t l = 0; l < kLanes && i + l < x.size(); ++l) v[l] = x[i + l];
    const RealLanes r = mpm::simd::log(v);
    for (std::size_t l = 0; l < kLanes && i + l < x.size(); ++l) out[i + l] = r[l];
  }
  return out;
}

/// Positive doubles, from random bits (the same on every build): `n` with random exponents over the whole
/// normal range and `n` in [0.5, 2) (the range of the Jacobian J in finite-strain materials), plus 1 +- k
/// ulps for k < 4096 (fdlibm has a separate branch for |f| < 2^-20 that the branch-free version folds into
/// the general formula).
std::vector<Real> positive_samples(int n) {
  std::mt19937_64 rng(20240917);
  std::uniform_int_distribution<std::uint64_t> exponent(1, 2046), mantissa(0, (std::uint64_t{1} << 52) - 1);
  std::uniform_int_distribution<std::uint64_t> near_one(1022, 1023);  // exponents of [0.5, 1) and [1, 2)
  std::vector<Real> x;
  for (int i = 0; i < n; ++i) x.push_back(std::bit_cast<Real>(exponent(rng) << 52 | mantissa(rng)));
  for (int i = 0; i < n; ++i) x.push_back(std::bit_cast<Real>(near_one(rng) << 52 | mantissa(rng)));
  for (int k = 1; k < 4096; ++k) {
    x.push_back(1.0 + k * std::numeric_limits<Real>::epsilon());
    x.push_back(1.0 - k * std::numeric_limits<Real>::epsilon() / 2);
  }
  return x;
}

/// Subnormals: every power of two 2^-1074 .. 2^-1023 and random mantissas.
std::vector<Real> subnormal_samples() {
  std::vector<Real> x;
  for (int k = 0; k < 52; ++k) x.push_back(std::bit_cast<Real>(std::uint64_t{1} << k));
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::uint64_t> mantissa(1, (std::uint64_t{1} << 52) - 1);
  for (int i = 0; i < 10000; ++i) x.push_back(std::bit_cast<Real>(mantissa(rng)));
  return x;
}

TEST(simd, lanes_match_the_register_width) {
  EXPECT_EQ(kLanes, sizeof(RealLanes) / 8);
  EXPECT_EQ(sizeof(mpm::simd::IntLanes), sizeof(RealLanes));
  const RealLanes b = mpm::simd::broadcast(2.5);
  for (int l = 0; l < lanes; ++l) EXPECT_EQ(b[l], 2.5);
}

// fdlibm's bound. Measured on these 1,008,190 inputs, with identical bits for 2 lanes (x86-64-v2), 4
// (x86-64-v3) and 8 (-march=native, AVX-512): max 1 ulp; 37,865 results (3.8%) are 1 ulp off std::log,
// 37,384 of them in [0.5, 2) (fdlibm's own branching version: 39,315).
TEST(simd_log, within_one_ulp_of_std_log) {
  const std::vector<Real> x = positive_samples(500000);
  const std::vector<Real> y = log_lanes(x);
  for (std::size_t i = 0; i < x.size(); ++i) ASSERT_LE(ulps(y[i], std::log(x[i])), 1) << "x = " << x[i];
}

TEST(simd_log, subnormals_within_one_ulp_of_std_log) {
  const std::vector<Real> x = subnormal_samples();
  const std::vector<Real> y = log_lanes(x);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_LE(ulps(y[i], std::log(x[i])), 1) << "x = " << x[i];
  constexpr Real smallest = std::numeric_limits<Real>::denorm_min();  // 2^-1074
  EXPECT_EQ(mpm::simd::log(smallest), std::log(smallest));
}

TEST(simd_log, is_exactly_zero_at_one) {
  const Real r = mpm::simd::log(1.0);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r), 0u);  // +0, not -0
  const RealLanes v = mpm::simd::log(mpm::simd::broadcast(1.0));
  for (int l = 0; l < lanes; ++l) EXPECT_EQ(std::bit_cast<std::uint64_t>(v[l]), 0u);
}

TEST(simd_log, special_values) {
  // Each special value in its own lane next to ordinary ones: the selection is per lane.
  using lim = std::numeric_limits<Real>;
  const std::vector<Real> x = {kInf,  0.0,        -0.0,       -1.0, -lim::denorm_min(), -kInf, kNaN,
                               -kNaN, lim::max(), lim::min(), 2.0};
  std::vector<Real> scalar;
  for (const Real v : x) scalar.push_back(mpm::simd::log(v));
  for (const std::vector<Real>& r : {log_lanes(x), scalar}) {
    EXPECT_EQ(r[0], kInf);
    EXPECT_EQ(r[1], -kInf);
    EXPECT_EQ(r[2], -kInf);
    for (int i = 3; i < 8; ++i) EXPECT_TRUE(std::isnan(r[i])) << "x = " << x[i];
    for (int i = 8; i < 11; ++i) EXPECT_LE(ulps(r[i], std::log(x[i])), 1) << "x = " << x[i];
  }
}

TEST(simd_log, scalar_overload_returns_the_bits_of_every_lane) {
  std::vector<Real> x = positive_samples(20000);
  for (const Real s : subnormal_samples()) x.push_back(s);
  for (const Real s : {kInf, 0.0, -0.0, -1.0, -kInf, kNaN}) x.push_back(s);
  // Every value visits every lane: the array is evaluated at each of the `lanes` offsets.
  for (std::size_t shift = 0; shift < kLanes; ++shift) {
    std::vector<Real> shifted(shift, 1.0);
    shifted.insert(shifted.end(), x.begin(), x.end());
    const std::vector<Real> y = log_lanes(shifted);
    for (std::size_t i = 0; i < shifted.size(); ++i)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(mpm::simd::log(shifted[i])), std::bit_cast<std::uint64_t>(y[i]))
          << "x = " << shifted[i] << ", lane " << i % kLanes;
  }
}

}  // namespace

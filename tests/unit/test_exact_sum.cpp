// ExactSum: the sum of doubles without rounding, read once rounded to nearest. Checked against sums whose
// exact value is known by construction, in every order and grouping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <random>
#include <vector>

#include "mpm/core/exact_sum.hpp"

namespace {

using mpm::ExactSum;

double exact_sum(const std::vector<double>& x) {
  ExactSum s;
  for (double v : x) s.add(v);
  return s.value();
}

TEST(ExactSum, CancellationThatDoubleAdditionLoses) {
  EXPECT_EQ(exact_sum({1e16, 1.0, -1e16}), 1.0);  // in doubles: 0
  EXPECT_EQ(exact_sum({1e308, 1e-308, -1e308}), 1e-308);
  EXPECT_EQ(exact_sum({0.1, 0.2, -0.3}),
            std::ldexp(1.0, -55));  // the doubles nearest 0.1, 0.2, 0.3 differ by 2^-55
  EXPECT_EQ(exact_sum({}), 0.0);
  EXPECT_EQ(exact_sum({-2.5}), -2.5);
}

TEST(ExactSum, RoundsOnceToNearest) {
  const double u = std::ldexp(1.0, -53);  // half an ulp of 1
  // 1 + u is a tie (rounds to even, 1); anything above it rounds up, which summing in doubles loses.
  EXPECT_EQ(exact_sum({1.0, u}), 1.0);
  EXPECT_EQ(exact_sum({1.0, u, std::ldexp(1.0, -90)}), 1.0 + 2 * u);
  EXPECT_EQ(exact_sum({1.0, u, u}), 1.0 + 2 * u);
  EXPECT_EQ(exact_sum({-1.0, -u, -std::ldexp(1.0, -200)}), -(1.0 + 2 * u));
}

TEST(ExactSum, SubnormalsAndTheEndsOfTheRange) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(exact_sum({tiny, tiny, tiny}), 3 * tiny);
  EXPECT_EQ(exact_sum({DBL_MAX, -DBL_MAX, tiny}), tiny);
  EXPECT_EQ(exact_sum({DBL_MAX, DBL_MAX}), INFINITY);  // the exact sum is beyond every double
  EXPECT_EQ(exact_sum({DBL_MAX, DBL_MAX, -DBL_MAX}), DBL_MAX);
  EXPECT_EQ(exact_sum({INFINITY, 1.0}), INFINITY);
  EXPECT_EQ(exact_sum({-INFINITY, 1.0}), -INFINITY);
  EXPECT_TRUE(std::isnan(exact_sum({INFINITY, -INFINITY})));
  EXPECT_TRUE(std::isnan(exact_sum({std::nan(""), 1.0})));
}

TEST(ExactSum, SameBitsInEveryOrderAndGrouping) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-60, 60);
  std::vector<double> x(5000);
  for (double& v : x) v = std::ldexp(mantissa(rng), exponent(rng));
  // The exact sum of x and -x plus a known value is that value; the double sum of the same terms is not.
  std::vector<double> terms = x;
  for (double v : x) terms.push_back(-v);
  terms.push_back(0.7);
  const double first = exact_sum(terms);
  EXPECT_EQ(first, 0.7);
  double naive = 0;
  for (double v : terms) naive += v;
  EXPECT_NE(naive, 0.7);
  for (int round = 0; round < 20; ++round) {
    std::shuffle(terms.begin(), terms.end(), rng);
    // Split into a random number of groups, each summed apart and merged, once directly and once through the
    // integers a rank would send.
    const std::size_t groups = 1 + rng() % 7;
    std::vector<ExactSum> part(groups);
    for (std::size_t i = 0; i < terms.size(); ++i) part[rng() % groups].add(terms[i]);
    ExactSum merged;
    std::vector<std::int64_t> integers(ExactSum::integer_count, 0);
    for (const ExactSum& p : part) {
      merged.add(p);
      const std::vector<std::int64_t> mine = p.integers();
      for (std::size_t k = 0; k < integers.size(); ++k) integers[k] += mine[k];
    }
    EXPECT_EQ(merged.value(), first);
    EXPECT_EQ(ExactSum::from_integers(integers).value(), first);
  }
}

}  // namespace

// The thread pool behind parallel_for: every index once, exceptions brought back, the same bits for any
// count.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "mpm/core/parallel.hpp"

namespace mpm {
namespace {

class ThreadCounts : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override { set_num_threads(GetParam()); }
  void TearDown() override { set_num_threads(0); }
};

TEST_P(ThreadCounts, EveryIndexRunsOnceOnAThreadOfThePool) {
  EXPECT_EQ(num_threads(), GetParam());
  for (std::ptrdiff_t n : {0, 1, 1023, 1024, 1025, 4096 * 3 + 7, 100000}) {
    std::vector<std::atomic<int>> runs(static_cast<std::size_t>(n));
    std::vector<int> thread(static_cast<std::size_t>(n), -1);
    parallel_for(n, [&](std::ptrdiff_t i) {
      runs[static_cast<std::size_t>(i)].fetch_add(1);
      thread[static_cast<std::size_t>(i)] = thread_index();
    });
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      ASSERT_EQ(runs[static_cast<std::size_t>(i)].load(), 1) << "n = " << n << ", i = " << i;
      ASSERT_GE(thread[static_cast<std::size_t>(i)], 0);
      ASSERT_LT(thread[static_cast<std::size_t>(i)], GetParam());
    }
  }
}

// Loops of changing length back to back: a thread still finishing one loop must claim nothing of the next (a
// claim that checked the next loop's chunk count against the previous loop's epoch ran a chunk twice and
// hung).
TEST_P(ThreadCounts, BackToBackLoopsOfChangingLengthRunEachIndexOnce) {
  constexpr int loops = 4000;
  std::vector<int> runs(4096, 0), expected(4096, 0);
  for (int r = 0; r < loops; ++r) {
    const std::ptrdiff_t n = 1024 + (r * 1237) % 3072;
    parallel_for(n, [&](std::ptrdiff_t i) { ++runs[static_cast<std::size_t>(i)]; });
    for (std::ptrdiff_t i = 0; i < n; ++i) ++expected[static_cast<std::size_t>(i)];
  }
  EXPECT_EQ(runs, expected);
}

TEST_P(ThreadCounts, ALoopInsideALoopRunsOnItsThread) {
  std::vector<std::atomic<int>> runs(64 * 2048);
  parallel_for(
      64,
      [&](std::ptrdiff_t i) {
        const int outer = thread_index();
        parallel_for(2048, [&](std::ptrdiff_t j) {
          EXPECT_EQ(thread_index(), outer);
          runs[static_cast<std::size_t>(i * 2048 + j)].fetch_add(1);
        });
      },
      1);
  for (const auto& r : runs) ASSERT_EQ(r.load(), 1);
}

TEST_P(ThreadCounts, AnExceptionFromABodyReachesTheCallerAndThePoolGoesOn) {
  EXPECT_THROW(parallel_for(100000,
                            [](std::ptrdiff_t i) {
                              if (i == 77777) throw std::runtime_error("body failed");
                            }),
               std::runtime_error);
  std::atomic<std::int64_t> sum{0};
  parallel_for(100000, [&](std::ptrdiff_t i) { sum.fetch_add(i); });
  EXPECT_EQ(sum.load(), std::int64_t{100000} * 99999 / 2);
}

TEST_P(ThreadCounts, ReductionsGiveTheBitsOfOneThread) {
  // A floating-point sum depends on its order; the blocks fix the order, whatever runs them.
  const std::ptrdiff_t n = 1'000'003;
  const auto value = [](std::ptrdiff_t i) { return 1.0 / static_cast<double>(i + 1); };
  const auto add = [](double a, double b) { return a + b; };
  const double here = parallel_reduce(n, 0.0, value, add);
  set_num_threads(1);
  const double alone = parallel_reduce(n, 0.0, value, add);
  EXPECT_EQ(here, alone);
  // The harmonic number H_n = ln n + gamma + 1/(2n) - ..., within the worst-case rounding n u H_n = 1.6e-9 of
  // the sum.
  EXPECT_NEAR(alone, std::log(static_cast<double>(n)) + 0.5772156649015329 + 0.5 / static_cast<double>(n),
              1.6e-9);
  EXPECT_EQ(parallel_reduce(
                n, false, [](std::ptrdiff_t i) { return i == n - 1; }, [](bool a, bool b) { return a || b; }),
            true);
}

INSTANTIATE_TEST_SUITE_P(Threads, ThreadCounts, ::testing::Values(1, 2, 3, 8));

TEST(ThreadCount, ZeroRestoresTheDefault) {
  set_num_threads(0);
  const int standard = num_threads();
  EXPECT_GE(standard, 1);
  set_num_threads(5);
  EXPECT_EQ(num_threads(), 5);
  set_num_threads(0);
  EXPECT_EQ(num_threads(), standard);
}

}  // namespace
}  // namespace mpm

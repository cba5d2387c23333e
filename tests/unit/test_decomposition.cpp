// The division of the grid between ranks (mpm/distributed/decomposition.hpp): boxes of whole tiles by
// recursive coordinate bisection weighted by particle counts. Checked: the boxes partition the tiles exactly;
// uniform weights give equal boxes where the counts divide; each cut shares the weight to within one tile
// layer of the ideal ratio; the result is a function of its arguments; a grid too small for the ranks is
// refused.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/distributed/decomposition.hpp"

namespace {

template <int Dim>
std::int64_t total_tiles(const mpm::IVec<Dim>& tiles) {
  std::int64_t n = 1;
  for (int d = 0; d < Dim; ++d) n *= tiles[d];
  return n;
}

/// The box each tile lies in; -1 where none, -2 where several.
template <int Dim>
std::vector<int> owners(const mpm::IVec<Dim>& tiles, const std::vector<mpm::TileBox<Dim>>& boxes) {
  std::vector<int> owner(static_cast<std::size_t>(total_tiles<Dim>(tiles)), -1);
  for (std::size_t flat = 0; flat < owner.size(); ++flat) {
    mpm::IVec<Dim> t;
    std::size_t rest = flat;
    for (int d = 0; d < Dim; ++d) {
      t[d] = static_cast<int>(rest % static_cast<std::size_t>(tiles[d]));
      rest /= static_cast<std::size_t>(tiles[d]);
    }
    for (std::size_t b = 0; b < boxes.size(); ++b)
      if (boxes[b].contains(t)) owner[flat] = owner[flat] == -1 ? static_cast<int>(b) : -2;
  }
  return owner;
}

TEST(Decomposition, BoxesPartitionTheTilesForEveryRankCount) {
  const mpm::IVec<3> tiles = {7, 5, 3};
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> particles(0, 100);
  std::vector<std::int64_t> weight(static_cast<std::size_t>(total_tiles<3>(tiles)));
  for (std::int64_t& w : weight) w = particles(rng);
  for (int ranks = 1; ranks <= 16; ++ranks) {
    const auto boxes = mpm::bisect<3>(tiles, weight, ranks);
    ASSERT_EQ(boxes.size(), static_cast<std::size_t>(ranks));
    std::vector<int> count(static_cast<std::size_t>(ranks), 0);
    for (int o : owners<3>(tiles, boxes)) {
      ASSERT_GE(o, 0) << "a tile in no box (-1) or in several (-2), " << ranks << " ranks";
      ++count[static_cast<std::size_t>(o)];
    }
    for (std::size_t r = 0; r < boxes.size(); ++r)
      EXPECT_EQ(count[r], boxes[r].tile_count()) << ranks << " ranks";
    EXPECT_EQ(mpm::bisect<3>(tiles, weight, ranks), boxes);  // a function of its arguments
  }
}

TEST(Decomposition, UniformWeightsGiveEqualBoxes) {
  // 16 x 8 tiles of 10 particles: 2 ranks cut the longer axis in half, 4 ranks give 4 x 8 quarters (the 8 x 8
  // halves are cut across the lowest of their equal axes), 8 ranks 4 x 4 eighths; all balanced exactly.
  const mpm::IVec<2> tiles = {16, 8};
  const std::vector<std::int64_t> weight(128, 10);
  EXPECT_EQ(mpm::bisect<2>(tiles, weight, 2),
            (std::vector<mpm::TileBox<2>>{{{0, 0}, {8, 8}}, {{8, 0}, {16, 8}}}));
  EXPECT_EQ(mpm::bisect<2>(tiles, weight, 4),
            (std::vector<mpm::TileBox<2>>{
                {{0, 0}, {4, 8}}, {{4, 0}, {8, 8}}, {{8, 0}, {12, 8}}, {{12, 0}, {16, 8}}}));
  for (int ranks : {1, 2, 4, 8, 16, 32})
    EXPECT_EQ(mpm::imbalance<2>(tiles, weight, mpm::bisect<2>(tiles, weight, ranks)), 1.0);
  // 3 ranks on 12 tiles in a row: 4 each (the cut for 1 : 2 at 4, then 2 : 2 at 8).
  EXPECT_EQ(mpm::bisect<1>({12}, std::vector<std::int64_t>(12, 5), 3),
            (std::vector<mpm::TileBox<1>>{{{0}, {4}}, {{4}, {8}}, {{8}, {12}}}));
}

TEST(Decomposition, CutsFollowTheParticles) {
  // A row of 20 tiles, the particles all in the last 4 (a body at one end of a long grid): 2 ranks share them
  // 2 : 2, cutting at tile 18; empty tiles go with the low box, so each rank has 40 particles.
  std::vector<std::int64_t> weight(20, 0);
  for (int t = 16; t < 20; ++t) weight[static_cast<std::size_t>(t)] = 20;
  const auto boxes = mpm::bisect<1>({20}, weight, 2);
  EXPECT_EQ(boxes[0].hi[0], 18);
  EXPECT_EQ(mpm::imbalance<1>({20}, weight, boxes), 1.0);
  // Random weights: every box's weight within one tile layer's weight of the ideal share. With layers of at
  // most 16 x 100 particles and 4 ranks (two levels of cuts), each box misses its share by less than 2
  // layers.
  const mpm::IVec<2> tiles = {40, 16};
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> particles(0, 100);
  std::vector<std::int64_t> w2(640);
  for (std::int64_t& w : w2) w = particles(rng);
  const std::int64_t total = std::accumulate(w2.begin(), w2.end(), std::int64_t{0});
  const auto four = mpm::bisect<2>(tiles, w2, 4);
  const double share = static_cast<double>(total) / 4;
  EXPECT_LT(mpm::imbalance<2>(tiles, w2, four), 1 + 2 * 16 * 100 / share);
  EXPECT_LT(mpm::imbalance<2>(tiles, w2, four), 1.05);  // measured 1.028
}

TEST(Decomposition, MoreRanksThanTheGridCanBeCutIntoIsRefused) {
  const std::vector<std::int64_t> weight(4, 1);
  EXPECT_EQ(mpm::bisect<2>({2, 2}, weight, 4).size(), 4u);
  EXPECT_THROW(mpm::bisect<2>({2, 2}, weight, 5), mpm::InputError);
  EXPECT_THROW(mpm::bisect<2>({2, 2}, weight, 0), mpm::InputError);
  EXPECT_THROW(mpm::bisect<2>({2, 3}, weight, 2), mpm::InputError);  // weights for another grid
}

}  // namespace

// The particle update both engines share (include/mpm/transfer/particle_update.hpp), lane by lane against
// values worked out by hand: the position kept to the grid (a periodic wrap, a wall's plane, an outflow face,
// a face that holds nothing), CPDI2's centroid with its corners following it, F^{n+1} = (I + dt grad v) F^n
// with its determinant, cpGIMP's half-lengths against the stencil, and the lowest faulty particle of a pass.
// Every value below is exact in binary floating point (sums and products of multiples of 1/8 and 1/16), so
// the assertions are equalities.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <limits>
#include <utility>

#include "mpm/transfer/particle_update.hpp"

namespace {
using namespace mpm;

/// Lane k of `values` (the remaining lanes repeat the last value).
RealLanes lanes(std::initializer_list<Real> values) {
  RealLanes out{};
  int k = 0;
  Real last = 0;
  for (Real v : values) out[k++] = last = v;
  for (; k < simd::lanes; ++k) out[k] = last;
  return out;
}

/// A 4 x 4 grid of unit cells from the origin: x periodic, a wall at y = 0, an outflow face at y = 4.
GridGeometry<2> periodic_wall_outflow() {
  GridGeometry<2> g;
  g.cells = {4, 4};
  g.periodic = {true, false};
  g.walls = {false, false, true, false};
  g.outflow = {false, false, false, true};
  return g;
}

TEST(ParticleUpdate, PositionsWrapStayOnWallsAndPassOnlyOutflowFaces) {
  static_assert(simd::lanes >= 4);
  const PositionBounds<2> bounds(periodic_wall_outflow());
  // Lane 0 leaves through x = 4 (periodic), lane 1 through y = 0 (a wall), lane 2 through y = 4 (outflow),
  // lane 3 stays inside.
  RecordLanes<Vec<2>> x = {lanes({3.5, 1, 1, 2}), lanes({1, 0.5, 3.5, 2})};
  const RecordLanes<Vec<2>> v = {lanes({8, 0, 0, 1}), lanes({0, -8, 8, 1})};
  RecordLanes<Corners<2>> unused;
  const simd::MaskLanes ok = move_positions<2, LinearKernel>(bounds, x, v, 0.125, unused);
  EXPECT_EQ(x[0][0], 0.5);  // 3.5 + 1 = 4.5, wrapped by the period 4
  EXPECT_EQ(x[1][1], 0.0);  // 0.5 - 1 = -0.5, back onto the wall
  EXPECT_EQ(x[1][2], 4.5);  // past the outflow face, where the particle is removed after the step
  EXPECT_EQ(x[0][3], 2.125);
  EXPECT_EQ(x[1][3], 2.125);
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(ok[k]) << "lane " << k;

  // The same motions on a grid whose faces hold nothing: lanes 0 and 2 leave it, lane 1 goes below y = 0.
  GridGeometry<2> open;
  open.cells = {4, 4};
  const PositionBounds<2> none(open);
  x = {lanes({3.5, 1, 1, 2}), lanes({1, 0.5, 3.5, 2})};
  const simd::MaskLanes inside = move_positions<2, LinearKernel>(none, x, v, 0.125, unused);
  EXPECT_FALSE(inside[0]);
  EXPECT_FALSE(inside[1]);
  EXPECT_FALSE(inside[2]);
  EXPECT_TRUE(inside[3]);
  EXPECT_EQ(x[0][0], 4.5);  // left where the velocity took it
}

TEST(ParticleUpdate, ACpdi2ParticleGoesToItsCornersCentroidAndTheyFollowItThroughAWrap) {
  // A unit square of corners centred at (4.25, 2), past the periodic face x = 4: the centroid (4.25, 2) wraps
  // to (0.25, 2) and the corners move by -4 with it. The velocity is not read.
  const PositionBounds<2> bounds(periodic_wall_outflow());
  RecordLanes<Vec<2>> x = {lanes({4.0}), lanes({2.0})};  // the old centre: a point near the corners
  RecordLanes<Corners<2>> corners;
  const Real cx[4] = {3.75, 4.75, 3.75, 4.75}, cy[4] = {1.5, 1.5, 2.5, 2.5};  // CpdiKernel::sign order
  for (int c = 0; c < 4; ++c) corners[0 + 2 * c] = lanes({cx[c]}), corners[1 + 2 * c] = lanes({cy[c]});
  const RecordLanes<Vec<2>> v = {lanes({1e9}), lanes({1e9})};
  const simd::MaskLanes ok = move_positions<2, Cpdi2Kernel<2>>(bounds, x, v, 1.0, corners);
  EXPECT_TRUE(ok[0]);
  EXPECT_EQ(x[0][0], 0.25);
  EXPECT_EQ(x[1][0], 2.0);
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(corners[0 + 2 * c][0], cx[c] - 4) << "corner " << c;
    EXPECT_EQ(corners[1 + 2 * c][0], cy[c]) << "corner " << c;
  }
  // A folded domain (two corners swapped) is refused.
  x = {lanes({4.0}), lanes({2.0})};
  for (int c = 0; c < 4; ++c) corners[0 + 2 * c] = lanes({cx[c]}), corners[1 + 2 * c] = lanes({cy[c]});
  std::swap(corners[0 + 2 * 0], corners[0 + 2 * 1]);
  EXPECT_FALSE((move_positions<2, Cpdi2Kernel<2>>(bounds, x, v, 1.0, corners)[0]));
}

TEST(ParticleUpdate, DeformationGradientAndItsDeterminant) {
  // F^n = [[1, 1/8], [0, 1]], grad v = [[4, 0], [1, -4]], dt = 1/16: I + dt grad v = [[5/4, 0], [1/16, 3/4]],
  // F^{n+1} = [[5/4, 5/32], [1/16, 3/4 + 1/128]], det = 5/4 (97/128) - 5/32 / 16 = 485/512 - 5/512 = 480/512.
  RecordLanes<Mat<2>> F_old;  // column-major: (0,0), (1,0), (0,1), (1,1)
  F_old[0] = lanes({1}), F_old[1] = lanes({0}), F_old[2] = lanes({0.125}), F_old[3] = lanes({1});
  const Real L[2][2] = {{4, 0}, {1, -4}};
  RealLanes F[2][2];
  RecordLanes<Mat<2>> F_new;
  const RealLanes J = deform<2>([&](int a, int c) { return lanes({L[a][c]}); }, 0.0625, F_old, F, F_new);
  EXPECT_EQ(F[0][0][0], 1.25);
  EXPECT_EQ(F[0][1][0], 0.15625);
  EXPECT_EQ(F[1][0][0], 0.0625);
  EXPECT_EQ(F[1][1][0], 0.7578125);
  EXPECT_EQ(F_new[2][0], F[0][1][0]);  // entry (0, 1) of the column-major record
  EXPECT_EQ(J[0], 0.9375);
}

TEST(ParticleUpdate, CpGimpHalfLengthsAreBoundedToTheStencil) {
  // l0 = 1/4, a bound of 1/2: inside [l0/4, 1/2] l0 F_dd itself (Eq. (63)), both ends included; past the
  // bound the bound; below l0/4 = 1/16 that floor; a negative F_dd (a rotation past a right angle) its
  // magnitude, within the same interval. The same in lanes and in one value.
  const std::pair<Real, Real> cases[] = {{1.5, 0.375},   {0.5, 0.125},   {2, 0.5},       {2.5, 0.5},
                                         {40, 0.5},      {0.25, 0.0625}, {0.1, 0.0625},  {0, 0.0625},
                                         {-0.0, 0.0625}, {-0.5, 0.125},  {-0.1, 0.0625}, {-3, 0.5}};
  for (const auto& [F_dd, l] : cases) {
    EXPECT_EQ(deformed_half_length(0.25, F_dd, 0.5), l) << "F_dd = " << F_dd;
    EXPECT_EQ(deformed_half_length(lanes({0.25}), lanes({F_dd}), 0.5)[0], l) << "F_dd = " << F_dd;
  }
  // A set's half_length and half_length_bounded agree with it.
  ParticleSet<2> p;
  p.add(Vec<2>(0.5, 0.5), Vec<2>::Zero(), 1, 1, Vec<2>(0.25, 0.25), 0);
  p.half_lengths = HalfLengths::deformed;
  p.max_half_length = 0.5;
  p.F[0] << 1.5, 0.3, -0.2, 0.5;
  EXPECT_EQ(p.half_length(0), Vec<2>(0.375, 0.125));
  EXPECT_FALSE(p.half_length_bounded(0));
  p.F[0](1, 1) = -0.5;
  EXPECT_EQ(p.half_length(0), Vec<2>(0.375, 0.125));
  EXPECT_TRUE(p.half_length_bounded(0));
  p.F[0](1, 1) = 0.5, p.F[0](0, 0) = 2.5;
  EXPECT_EQ(p.half_length(0), Vec<2>(0.5, 0.125));
  EXPECT_TRUE(p.half_length_bounded(0));
}

TEST(ParticleUpdate, TheLowestFaultyParticleIsKept) {
  std::atomic<std::int64_t> first{std::numeric_limits<std::int64_t>::max()};
  const std::ptrdiff_t n = 3 * simd::lanes;
  simd::MaskLanes all_ok = simd::MaskLanes{} == 0, last_lane = all_ok, second_lane = all_ok;
  last_lane[simd::lanes - 1] = 0;
  second_lane[1] = 0;
  note_first_fault(first, LaneBlock(2, n), last_lane);
  EXPECT_EQ(first.load(), 3 * simd::lanes - 1);
  note_first_fault(first, LaneBlock(1, n), second_lane);
  EXPECT_EQ(first.load(), simd::lanes + 1);
  note_first_fault(first, LaneBlock(0, n), all_ok);
  note_first_fault(first, LaneBlock(2, n), second_lane);  // higher: kept out
  EXPECT_EQ(first.load(), simd::lanes + 1);
}

}  // namespace

// Multi-field contact (contact/multi_field.hpp) by hand-computed cases: the normals of a pair, the momentum a
// pair exchanges (Coulomb, stick), the correction at a node of two small grids with its force and dissipated
// power, and the refusal of contact specs without meaning.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "mpm/contact/multi_field.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/grid/grid.hpp"

namespace {

using mpm::ContactNormal;
using mpm::Real;
using V2 = mpm::Vec<2>;

TEST(MultiFieldContact, NormalsOfAPair) {
  // Body a above b: a's volume gradient points down (out of a), b's up; the normal from a into b points down.
  const V2 g_a(0.1, -1), g_b(0, 3);
  const V2 average = mpm::contact_normal<2>(g_a, g_b, ContactNormal::average);
  EXPECT_NEAR(average.x(), 0.1 / std::hypot(0.1, 4.0), 1e-15);
  EXPECT_NEAR(average.y(), -4 / std::hypot(0.1, 4.0), 1e-15);
  EXPECT_EQ(mpm::contact_normal<2>(g_a, g_b, ContactNormal::larger), V2(0, -1));  // b's is longer: -g_b
  const V2 first = mpm::contact_normal<2>(g_a, g_b, ContactNormal::first);
  EXPECT_NEAR(first.x(), 0.1 / std::hypot(0.1, 1.0), 1e-15);
  // Undefined where both gradients vanish: zero, and then no Coulomb correction applies.
  EXPECT_EQ(mpm::contact_normal<2>(V2::Zero(), V2::Zero(), ContactNormal::average), V2::Zero());
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, V2(0, -1), 1, V2::Zero(), V2::Zero(), 0.3), V2::Zero());
}

TEST(MultiFieldContact, MomentumAPairExchanges) {
  // m_a = 1 moving down at 2 m/s and sideways at 3 m/s onto m_b = 3 at rest; n from a into b is (0, -1).
  // Reduced mass 3/4: frictionless, a gains 3/4 (0, 2); with mu = 0.5 also 3/4 (-1, 0); with no law both take
  // the center-of-mass velocity (3/4, -1/2), a gaining 1 * ((3/4, -1/2) - (3, -2)).
  const V2 n(0, -1), v_a(3, -2), v_b(0, 0);
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, v_a, 3, v_b, n, 0.0), V2(0, 1.5));
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, v_a, 3, v_b, n, 0.5), V2(-0.75, 1.5));
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, v_a, 3, v_b, n, std::numeric_limits<Real>::infinity()),
            V2(-2.25, 1.5));
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, v_a, 3, v_b, n, -1), V2(-2.25, 1.5));
  // Moving apart: nothing unless they stick.
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, V2(3, 2), 3, v_b, n, 0.5), V2::Zero());
  EXPECT_EQ(mpm::pair_momentum_change<2>(1, V2(3, 2), 3, v_b, n, -1), V2(-2.25, -1.5));
}

TEST(MultiFieldContact, CorrectsANodeWhereTwoFieldsMeet) {
  // Two fields on a 1 x 1 grid (4 nodes): only node 0 holds both. Field 0 (m = 1) at v_new (3, -2) above
  // field 1 (m = 3) at rest, gradients (0, -1) and (0, 1): normal (0, -1), friction 0.5.
  mpm::GridGeometry<2> geometry{V2::Zero(), 1.0, {1, 1}, 0};
  mpm::Grid<2> a(geometry), b(geometry);
  a.nodes[0].m = 1, a.nodes[0].v_new = V2(0, -1);  // the volume gradients, where the mass pass leaves them
  b.nodes[0].m = 3, b.nodes[0].v_new = V2(0, 1);
  a.nodes[1].m = 2;  // field 0 alone
  mpm::MultiFieldContact<2> contact(mpm::ContactSpec{2, {{0, 1, 0.5, ContactNormal::average}}});
  const std::vector<mpm::Grid<2>*> fields{&a, &b};
  contact.locate(fields, 1e-12, mpm::IVec<2>{2, 2});
  EXPECT_EQ(contact.contact_nodes(), 1u);
  a.nodes[0].v_new = V2(3, -2), b.nodes[0].v_new = V2::Zero();
  a.nodes[0].a = b.nodes[0].a = V2::Zero();
  const Real dt = 0.5;
  contact.correct_update(fields, dt);
  // a gains (-0.75, 1.5) of momentum, b loses it; the accelerations take the changes over dt.
  EXPECT_EQ(a.nodes[0].v_new, V2(2.25, -0.5));
  EXPECT_EQ(b.nodes[0].v_new, V2(0.25, -0.5));
  EXPECT_EQ(a.nodes[0].a, V2(-1.5, 3));
  EXPECT_EQ(b.nodes[0].a, V2(0.5, -1));
  // On field 0 by field 1: force (-1.5, 3) N, compressive normal 3 N, tangential 1.5 N = mu x 3 N; friction
  // dissipates minus the force times the slip after, -(-1.5, 3) . (2, 0) = 3 W.
  const auto& sums = contact.pair_sums()[0];
  EXPECT_EQ(sums[0].value(), -1.5);
  EXPECT_EQ(sums[1].value(), 3.0);
  EXPECT_EQ(sums[2].value(), 3.0);
  EXPECT_EQ(sums[3].value(), 1.5);
  EXPECT_EQ(sums[4].value(), 3.0);
  // Total momentum unchanged: 1 (3, -2) + 3 (0, 0) = 1 (2.25, -0.5) + 3 (0.25, -0.5).
  EXPECT_EQ(a.nodes[0].m * a.nodes[0].v_new + b.nodes[0].m * b.nodes[0].v_new, V2(3, -2));
}

TEST(MultiFieldContact, ThreeFieldsAtANodeKeepTheirMomentum) {
  // Three fields at node 0, corrected pair by pair in field order: (0, 1) and (0, 2) by Coulomb friction, (1,
  // 2) in no pair, so stuck together. Every pair moves momentum from one field to the other: the sum stays.
  mpm::GridGeometry<2> geometry{V2::Zero(), 1.0, {1, 1}, 0};
  std::vector<mpm::Grid<2>> grids(3, mpm::Grid<2>(geometry));
  const V2 gradient[3] = {V2(0, -1), V2(0, 1), V2(1, 1)}, velocity[3] = {V2(3, -2), V2(0, 0.5), V2(-1, -1)};
  const Real mass[3] = {1, 3, 2};
  for (int k = 0; k < 3; ++k) grids[k].nodes[0].m = mass[k], grids[k].nodes[0].v_new = gradient[k];
  mpm::MultiFieldContact<2> contact(mpm::ContactSpec{3, {{0, 1, 0.3}, {0, 2, 0.0}}});
  const std::vector<mpm::Grid<2>*> fields{&grids[0], &grids[1], &grids[2]};
  contact.locate(fields, 1e-12, mpm::IVec<2>{2, 2});
  EXPECT_EQ(contact.contact_nodes(), 1u);
  V2 before = V2::Zero(), after = V2::Zero();
  for (int k = 0; k < 3; ++k) {
    grids[k].nodes[0].v_new = velocity[k];
    grids[k].nodes[0].a.setZero();
    before += mass[k] * velocity[k];
  }
  contact.correct_update(fields, 0.1);
  for (int k = 0; k < 3; ++k) after += mass[k] * grids[k].nodes[0].v_new;
  EXPECT_NEAR((after - before).norm(), 0.0, 1e-14);
  // The stuck pair (1, 2), corrected last, ends at one velocity.
  EXPECT_NEAR((grids[1].nodes[0].v_new - grids[2].nodes[0].v_new).norm(), 0.0, 1e-15);
  EXPECT_NE(grids[0].nodes[0].v_new, velocity[0]);
}

TEST(MultiFieldContact, SpecsWithoutMeaningAreRefused) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  for (const mpm::ContactSpec& bad :
       {mpm::ContactSpec{0, {}}, mpm::ContactSpec{256, {}}, mpm::ContactSpec{2, {{0, 2, 0.1}}},
        mpm::ContactSpec{2, {{1, 1, 0.1}}}, mpm::ContactSpec{2, {{0, 1, -0.1}}},
        mpm::ContactSpec{2, {{0, 1, nan}}}, mpm::ContactSpec{3, {{0, 1, 0.1}, {1, 0, 0.2}}}})
    EXPECT_THROW(mpm::validate(bad), mpm::InputError);
  EXPECT_NO_THROW(
      mpm::validate(mpm::ContactSpec{3, {{0, 1, 0.1}, {1, 2, std::numeric_limits<Real>::infinity()}}}));
}

}  // namespace

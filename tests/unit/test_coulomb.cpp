// The Coulomb contact law (contact/coulomb.hpp) by hand-computed cases, a Coulomb wall's correction,
// reaction, dissipated power and the spread of its normal force (KinematicConstraints), and the refusal of
// friction where it has no meaning.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "mpm/boundary/boundary.hpp"
#include "mpm/contact/coulomb.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/grid/grid.hpp"

namespace {

using mpm::Real;
using V2 = mpm::Vec<2>;

TEST(CoulombContact, LeavesASeparatingBodyAlone) {
  const V2 n(0, -1);  // from the body into the partner below it
  EXPECT_EQ(mpm::coulomb_contact<2>(V2(3, 1), n, 0.5), V2::Zero());  // moving up, away
  EXPECT_EQ(mpm::coulomb_contact<2>(V2(3, 0), n, 0.5), V2::Zero());  // sliding along it
}

TEST(CoulombContact, RemovesTheApproachAndLimitsTheSlipByMuTimesIt) {
  const V2 n(0, -1);
  // Approach 2 m/s, slip 3 m/s: frictionless keeps the slip; mu = 0.5 takes 1 m/s of it; mu = 2 all of it.
  EXPECT_EQ(mpm::coulomb_contact<2>(V2(3, -2), n, 0.0), V2(0, 2));
  EXPECT_EQ(mpm::coulomb_contact<2>(V2(3, -2), n, 0.5), V2(-1, 2));
  EXPECT_EQ(mpm::coulomb_contact<2>(V2(3, -2), n, 2.0), V2(-3, 2));
  // A slanted normal: the change is -approach n minus mu approach along the slip's direction.
  const V2 m = V2(1, -1).normalized();
  const V2 v(1, -3);  // approach (1 + 3)/sqrt 2, slip v - approach m = (-1, -1)
  const V2 change = mpm::coulomb_contact<2>(v, m, 0.25);
  const Real approach = 4 / std::sqrt(2.0);
  EXPECT_NEAR(change.dot(m), -approach, 1e-15);
  const V2 slip_after = (v + change) - (v + change).dot(m) * m;
  EXPECT_NEAR(slip_after.norm(), std::sqrt(2.0) - 0.25 * approach, 1e-15);
}

TEST(CoulombWall, CorrectsANodeAndReportsItsForceAndDissipation) {
  // One cell, the y-min face a fixed wall with mu = 0.5; every node there (and its ghost layer) has mass 2 kg
  // and advanced velocity (3, -2) m/s; dt = 0.1 s. Each node: dv = (-1, 2), force m dv / dt = (-20, 40) N,
  // power -force . v_after = -(-20 * 2 + 40 * 0) = 40 W.
  mpm::BoundarySpec<2> spec;
  spec.faces[2].type = mpm::FaceType::velocity;
  spec.faces[2].friction = 0.5;
  const mpm::GridGeometry<2> g{V2(0, 0), 1.0, {1, 1}, 1};
  mpm::KinematicConstraints<2> walls(spec, g);
  mpm::Grid<2> grid(g);
  int wall_nodes = 0;
  for (std::size_t n = 0; n < grid.size(); ++n) {
    grid.nodes[n].m = 2;
    grid.nodes[n].v_new = V2(3, -2);
    wall_nodes += g.coords(static_cast<std::ptrdiff_t>(n))[1] <= 0;
  }
  walls.constrain_update(grid, 0.1, 0.1);
  EXPECT_EQ(wall_nodes, 2 * 4);  // the face plane and the ghost layer below, 4 nodes each
  for (std::size_t n = 0; n < grid.size(); ++n) {
    const bool wall = g.coords(static_cast<std::ptrdiff_t>(n))[1] <= 0;
    EXPECT_EQ(grid.nodes[n].v_new, wall ? V2(2, 0) : V2(3, -2));
    EXPECT_EQ(grid.nodes[n].a, wall ? V2(-10, 20) : V2(0, 0));
  }
  EXPECT_EQ(walls.reactions()[0], V2(-20.0 * wall_nodes, 40.0 * wall_nodes));
  EXPECT_EQ(walls.friction_power().value(), 40.0 * wall_nodes);
  // The moments of the normal force, 40 N at each wall node, x = -1, 0, 1, 2 on both layers: sum 320 N, first
  // moment 40 * 2 * 2 = 160 N m, second 40 * 2 * 6 = 480 N m^2, none along the normal; spread
  // sqrt(480 / 320 - (160 / 320)^2) = sqrt(1.25) m.
  std::array<Real, 5> moments;
  for (int k = 0; k < 5; ++k) moments[k] = walls.normal_force_moments()[0][k].value();
  EXPECT_EQ(moments, (std::array<Real, 5>{320, 160, 0, 480, 0}));
  EXPECT_EQ(mpm::contact_spread<2>(moments), std::sqrt(1.25));
  EXPECT_EQ(mpm::contact_spread<2>({0, 0, 0, 0, 0}), 0.0);
}

TEST(CoulombWall, FrictionWithoutMeaningIsRefused) {
  const mpm::IVec<2> cells{4, 4};
  const auto refused = [&](mpm::FaceType type, Real mu) {
    mpm::BoundarySpec<2> spec;
    spec.faces[0].type = type;
    spec.faces[0].friction = mu;
    try {
      mpm::validate_faces<2>(spec, cells, mpm::Geometry::plane_strain, 0.0, "");
    } catch (const mpm::InputError&) {
      return true;
    }
    return false;
  };
  EXPECT_FALSE(refused(mpm::FaceType::velocity, 0.3));
  EXPECT_FALSE(refused(mpm::FaceType::velocity, -1));  // no friction: a no-slip wall
  EXPECT_TRUE(refused(mpm::FaceType::symmetry, 0.3));
  EXPECT_TRUE(refused(mpm::FaceType::velocity, std::numeric_limits<Real>::infinity()));
  EXPECT_TRUE(refused(mpm::FaceType::velocity, std::numeric_limits<Real>::quiet_NaN()));
}

}  // namespace

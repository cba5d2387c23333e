// Polygon bodies: the outline's geometry (inside test, area, centroid, self-crossing), and the particles a
// scene seeds in it, whose volume and centroid converge to the outline's as the spacing shrinks.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/geometry/polygon.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {
namespace {

/// An L of two unit squares on a 2 x 1 base: area 3, centroid (5/6, 5/6) by the composite-area formula.
Polygon l_shape() {
  return {{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}};
}

TEST(PolygonGeometry, AreaCentroidAndInsideOfAnL) {
  const Polygon l = l_shape();
  EXPECT_DOUBLE_EQ(l.signed_area(), 3.0);
  EXPECT_NEAR(l.centroid()[0], 5.0 / 6, 1e-15);
  EXPECT_NEAR(l.centroid()[1], 5.0 / 6, 1e-15);
  Polygon clockwise{{l.vertices.rbegin(), l.vertices.rend()}};
  EXPECT_DOUBLE_EQ(clockwise.signed_area(), -3.0);  // the same region the other way round
  EXPECT_NEAR(clockwise.centroid()[0], 5.0 / 6, 1e-15);
  for (const Polygon& p : {l, clockwise}) {
    EXPECT_TRUE(p.contains({0.5, 1.5}));
    EXPECT_TRUE(p.contains({1.5, 0.5}));
    EXPECT_FALSE(p.contains({1.5, 1.5}));  // the notch
    EXPECT_FALSE(p.contains({-0.1, 0.5}));
    EXPECT_FALSE(p.contains({0.5, 2.1}));
  }
  EXPECT_EQ(l.bounds().first, Vec<2>(0, 0));
  EXPECT_EQ(l.bounds().second, Vec<2>(2, 2));
}

TEST(PolygonGeometry, OutwardNormalIsTheSignedDistancesGradient) {
  // The L either way round: on an edge its outward normal; off the outline the unit vector from the nearest
  // outline point, outward (outside) or toward it (inside); off a convex corner the diagonal, in the notch
  // the normals of the edges that bound it.
  const Polygon l = l_shape();
  const Polygon clockwise{{l.vertices.rbegin(), l.vertices.rend()}};
  const Real r = std::sqrt(0.5);
  struct Case {
    Vec<2> x, n;
  };
  for (const Polygon& p : {l, clockwise})
    for (const Case& c : {Case{{1.5, 0}, {0, -1}}, Case{{0.5, -0.3}, {0, -1}}, Case{{0.5, 0.1}, {0, -1}},
                          Case{{2.5, 0.5}, {1, 0}}, Case{{1.9, 0.5}, {1, 0}}, Case{{2.2, 1.2}, {r, r}},
                          Case{{1.5, 1.2}, {0, 1}}, Case{{1.2, 1.5}, {1, 0}}, Case{{0.5, 2}, {0, 1}},
                          Case{{-1, -1}, {-r, -r}}}) {
      const Vec<2> n = p.outward_normal(c.x);
      EXPECT_NEAR(n[0], c.n[0], 1e-15) << c.x.transpose();
      EXPECT_NEAR(n[1], c.n[1], 1e-15) << c.x.transpose();
    }
  // A slab tilted by 30 degrees: the normal of its upper face above it, on it and just inside.
  const Real c30 = std::cos(M_PI / 6), s30 = std::sin(M_PI / 6);
  const Polygon slab{
      {{0, 0}, {2 * c30, -2 * s30}, {2 * c30 + 0.1 * s30, -2 * s30 - 0.1 * c30}, {0.1 * s30, -0.1 * c30}}};
  for (const Real above : {0.3, 0.0, -0.02}) {
    const Vec<2> n = slab.outward_normal(Vec<2>(c30, -s30) + above * Vec<2>(s30, c30));
    EXPECT_NEAR(n[0], s30, 1e-15) << above;
    EXPECT_NEAR(n[1], c30, 1e-15) << above;
  }
}

TEST(PolygonGeometry, CrossingsFound) {
  EXPECT_FALSE(first_crossing(l_shape()));
  const auto bowtie = first_crossing({{{0, 0}, {1, 1}, {1, 0}, {0, 1}}});
  ASSERT_TRUE(bowtie);
  EXPECT_EQ(*bowtie, std::make_pair(std::size_t{0}, std::size_t{2}));
  // Edge 1 folds back along edge 0.
  const auto fold = first_crossing({{{0, 0}, {2, 0}, {1, 0}, {1, 1}}});
  ASSERT_TRUE(fold);
  EXPECT_EQ(*fold, std::make_pair(std::size_t{0}, std::size_t{1}));
  // Vertex 4 touches edge 0 away from its ends.
  const auto touch = first_crossing({{{0, 0}, {2, 0}, {2, 1}, {1.5, 1}, {1, 0}, {0, 1}}});
  ASSERT_TRUE(touch);
  EXPECT_EQ(touch->first, 0u);
}

/// A scene of one polygon body (a slope: a 3 m base, a 1 m crest, 1 m high) on a 4 x 2 m grid of 0.25 m
/// cells, and a box beside it.
std::string slope_scene(int ppc) {
  return R"([simulation]
dimension = 2
end_time = 0.01
integrator = "usl"
kernel = "bspline2"
cfl = 0.4
[grid]
lo = [0.0, 0.0]
hi = [4.0, 2.0]
cells = [16, 8]
[[materials]]
name = "soil"
E = 1e7
nu = 0.3
density = 2000.0
[[bodies]]
name = "slope"
shape = "polygon"
vertices = [[0.25, 0.25], [3.25, 0.25], [1.25, 1.25], [0.25, 1.25]]
ppc = )" +
         std::to_string(ppc) + "\n";
}

// The seeded volume and its centroid against the outline's. The other edges lie on lines of the particle
// lattice's cells (multiples of s = h / ppc), so only the cells the slanted edge cuts can be counted wrongly,
// each by at most its area s^2; a segment spanning dx and dy cuts at most (|dx| + |dy|) / s + 1 cells (one
// per cell line it crosses, and the first), here dx = 2 m, dy = 1 m: |V - A| <= (3 / s + 1) s^2. A cell
// counted wrongly moves the centroid by at most its volume times its distance from the centroid (at most the
// body's diameter, sqrt(10) m) over V; the midpoint rule integrates x exactly over the cells counted rightly.
TEST(PolygonBody, VolumeAndCentroidConvergeToTheOutlines) {
  const Polygon outline{{{0.25, 0.25}, {3.25, 0.25}, {1.25, 1.25}, {0.25, 1.25}}};
  const Real area = outline.signed_area();
  ASSERT_DOUBLE_EQ(area, 2.0);
  const Real diameter = std::hypot(3.0, 1.0);
  for (int ppc : {1, 2, 4, 8}) {
    const Scene sc = read_scene_text(slope_scene(ppc), "slope.toml");
    const ParticleSet<2> p = seed_bodies<2>(sc);
    Real V = 0;
    Vec<2> moment = Vec<2>::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      V += p.V0[i];
      moment += p.V0[i] * p.X[i];
      EXPECT_TRUE(outline.contains(p.X[i]));
      EXPECT_DOUBLE_EQ(p.m[i], 2000.0 * p.V0[i]);
    }
    const Real s = 0.25 / ppc, bound = (3 / s + 1) * s * s;
    EXPECT_LE(std::abs(V - area), bound) << "ppc " << ppc;
    EXPECT_LE((moment / V - outline.centroid()).norm(), bound / V * diameter) << "ppc " << ppc;
  }
}

// A rectangle given as a polygon seeds what a box body seeds: the same lattice (that of a box from the grid's
// corner), so bodies of either kind meet without gaps.
TEST(PolygonBody, RectangleSeedsTheBoxLattice) {
  std::string polygon = slope_scene(2);
  polygon.replace(polygon.find("[1.25, 1.25]"), 12, "[3.25, 1.25]");
  std::string box = polygon;
  box.replace(box.find("shape = \"polygon\""), 17, "shape = \"box\"");
  box.replace(box.find("vertices = "), box.find("\nppc") - box.find("vertices = "),
              "lo = [0.25, 0.25]\nhi = [3.25, 1.25]");
  const ParticleSet<2> a = seed_bodies<2>(read_scene_text(polygon, "a.toml"));
  const ParticleSet<2> b = seed_bodies<2>(read_scene_text(box, "b.toml"));
  ASSERT_EQ(a.size(), 12u * 4 * 4);  // 12 x 4 cells, 2 x 2 particles each
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR((a.X[i] - b.X[i]).norm(), 0, 1e-14);
    EXPECT_EQ(a.V0[i], b.V0[i]);
  }
}

TEST(PolygonBody, RefusedOutsideTwoDimensions) {
  std::string text = slope_scene(2);
  text.replace(text.find("dimension = 2"), 13, "dimension = 3");
  text.replace(text.find("lo = [0.0, 0.0]"), 15, "lo = [0.0, 0.0, 0.0]");
  text.replace(text.find("hi = [4.0, 2.0]"), 15, "hi = [4.0, 2.0, 1.0]");
  text.replace(text.find("cells = [16, 8]"), 15, "cells = [16, 8, 4]");
  try {
    read_scene_text(text, "slope3d.toml");
    FAIL() << "a polygon in a 3-D scene was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].shape: \"polygon\" is for 2-D scenes"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mpm

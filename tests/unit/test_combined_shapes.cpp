// Bodies combined from shapes: a plate with a hole (a box minus a disk), two boxes added, a box cut to a
// disk, a polygon minus a polygon: the points of one lattice that lie in the union, every intersected shape
// and no subtracted one, each once.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>

#include "mpm/core/errors.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {
namespace {

/// One body on a 2 x 2 m grid of 0.25 m cells, 4 particles per cell per axis (s = 1/16 m): `body` holds its
/// shape's keys and its combinations.
ParticleSet<2> seed(const std::string& body) {
  const std::string text = R"([simulation]
dimension = 2
end_time = 0.01
integrator = "usl"
kernel = "bspline2"
cfl = 0.4
[grid]
lo = [0.0, 0.0]
hi = [2.0, 2.0]
cells = [8, 8]
[[materials]]
name = "steel"
E = 2e11
nu = 0.3
density = 7800.0
[[bodies]]
name = "part"
ppc = 4
)" + body + "\n";
  return seed_bodies<2>(read_scene_text(text, "combined.toml"));
}

Real volume(const ParticleSet<2>& p) {
  Real V = 0;
  for (std::size_t i = 0; i < p.size(); ++i) V += p.V0[i];
  return V;
}

/// No two particles at one place.
void expect_distinct(const ParticleSet<2>& p) {
  std::set<std::pair<Real, Real>> at;
  for (std::size_t i = 0; i < p.size(); ++i) at.insert({p.X[i][0], p.X[i][1]});
  EXPECT_EQ(at.size(), p.size());
}

constexpr Real s = 1.0 / 16;

// The plate [0.5, 1.5]^2 with a hole of radius 0.25 at its centre: no particle in the hole, and the volume
// within the cells the circle cuts: a circle of radius r crosses at most 8 r / s cell lines, so at most 8 r /
// s + 4 cells, each counted wrongly by at most s^2.
TEST(CombinedShapes, PlateWithAHole) {
  const ParticleSet<2> p = seed(
      "lo = [0.5, 0.5]\nhi = [1.5, 1.5]\nsubtract = [{ shape = \"disk\", center = [1.0, 1.0], radius = 0.25 "
      "}]");
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_GT((p.X[i] - Vec<2>(1, 1)).norm(), 0.25);
  EXPECT_NEAR(volume(p), 1 - M_PI / 16, (8 * 0.25 / s + 4) * s * s);
  expect_distinct(p);
}

// Two boxes that overlap by a quarter: 0.4375 m^2 exactly (every edge on a lattice line), each point once.
TEST(CombinedShapes, AddedBoxesCountTheOverlapOnce) {
  const ParticleSet<2> p =
      seed("lo = [0.5, 0.5]\nhi = [1.0, 1.0]\nadd = [{ lo = [0.75, 0.75], hi = [1.25, 1.25] }]");
  EXPECT_EQ(p.size(), 112u);  // 0.4375 / s^2
  EXPECT_DOUBLE_EQ(volume(p), 0.4375);
  expect_distinct(p);
}

// A box cut to the disk of radius 0.5 at its corner: the quarter disk, within the cells its arc cuts.
TEST(CombinedShapes, IntersectedWithADisk) {
  const ParticleSet<2> p = seed(
      "lo = [0.5, 0.5]\nhi = [1.5, 1.5]\nintersect = [{ shape = \"disk\", center = [0.5, 0.5], radius = 0.5 "
      "}]");
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_LE((p.X[i] - Vec<2>(0.5, 0.5)).norm(), 0.5);
    EXPECT_TRUE(p.X[i][0] > 0.5 && p.X[i][1] > 0.5);
  }
  EXPECT_NEAR(volume(p), M_PI / 16, (2 * 0.5 / s + 2) * s * s);  // the quarter arc crosses 2 r / s lines
}

// An L from a square minus a square, and the same L as one polygon: the same points.
TEST(CombinedShapes, PolygonMinusPolygonIsTheLPolygon) {
  const ParticleSet<2> cut = seed(
      "shape = \"polygon\"\nvertices = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]]\n"
      "subtract = [{ shape = \"polygon\", vertices = [[1.0, 1.0], [1.6, 1.0], [1.6, 1.6], [1.0, 1.6]] }]");
  const ParticleSet<2> l = seed(
      "shape = \"polygon\"\nvertices = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.0], [1.0, 1.0], [1.0, 1.5], [0.5, "
      "1.5]]");
  ASSERT_EQ(cut.size(), l.size());
  EXPECT_EQ(cut.size(), 192u);  // 0.75 m^2 / s^2
  for (std::size_t i = 0; i < l.size(); ++i) EXPECT_EQ(cut.X[i], l.X[i]);
}

TEST(CombinedShapes, AFileBodyIsNotCombined) {
  const std::filesystem::path csv =
      std::filesystem::temp_directory_path() / ("mpm_combined_" + std::to_string(::getpid()) + ".csv");
  std::ofstream(csv) << "x,y,volume\n1,1,0.001\n";
  try {
    seed("shape = \"file\"\nfile = \"" + csv.string() +
         "\"\nsubtract = [{ lo = [0.5, 0.5], hi = [1.0, 1.0] }]");
    FAIL() << "a file body with subtract was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "bodies[0].subtract: a particle file's or a mesh's body is not combined with shapes"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(csv);
}

}  // namespace
}  // namespace mpm

// Polygon bodies and rigid bodies run in both engines: a polygon falling freely under gravity from rest has
// the momentum -M g t at every step, M the mass of the particles the scene seeds in its outline; a rigid
// floor given as a polygon acts as the box of its corners.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "support.hpp"

namespace mpm {
namespace {

using testing::csv_columns;
using testing::run_mpm;
using testing::scratch;

/// A quarter-circle-like fan of a polygon (6 vertices) falling in an open 2 x 2 m grid for 0.05 s.
std::string fan_scene(const std::string& integrator) {
  return R"([simulation]
dimension = 2
end_time = 0.05
integrator = ")" +
         integrator + R"("
kernel = "bspline2"
cfl = 0.3
[grid]
lo = [0.0, 0.0]
hi = [2.0, 2.0]
cells = [20, 20]
[[materials]]
name = "rubber"
E = 1e6
nu = 0.3
density = 1100.0
[[bodies]]
name = "fan"
shape = "polygon"
vertices = [[0.5, 0.8], [1.5, 0.8], [1.45, 1.1], [1.3, 1.35], [1.05, 1.5], [0.5, 1.2]]
ppc = 3
[loads]
gravity = [0.0, -9.81]
)";
}

class PolygonRun : public ::testing::TestWithParam<std::string> {};

// Free fall: every node carries the same acceleration g, so the momentum is -M g t to round-off (relative
// 1e-12 over the 0.05 s: a few hundred steps of additions). The body stays clear of the grid's faces (it
// falls 12 mm).
TEST_P(PolygonRun, FallsWithTheMassOfItsParticles) {
  const std::string integrator = GetParam();
  const std::filesystem::path dir = scratch("mpm_polygon_run", integrator);
  const std::filesystem::path scene = dir / "fan.toml";
  std::ofstream(scene) << fan_scene(integrator);
  ASSERT_EQ(run_mpm(scene, "--out " + (dir / "out").string(), dir / "log"), 0) << testing::slurp(dir / "log");
  const ParticleSet<2> p = seed_bodies<2>(read_scene(scene));
  double M = 0;
  for (std::size_t i = 0; i < p.size(); ++i) M += p.m[i];
  EXPECT_NEAR(M, 1100.0 * static_cast<double>(p.size()) * std::pow(0.1 / 3, 2), 1e-9 * M);
  auto h = csv_columns(dir / "out" / "history.csv");
  ASSERT_GT(h["time"].size(), 2u);
  for (std::size_t k = 0; k < h["time"].size(); ++k) {
    EXPECT_NEAR(h["momentum_y"][k], -M * 9.81 * h["time"][k], 1e-12 * M * 9.81 * 0.05) << "row " << k;
    EXPECT_NEAR(h["momentum_x"][k], 0.0, 1e-12 * M * 9.81 * 0.05) << "row " << k;
  }
  std::filesystem::remove_all(dir);
}

/// A block dropped 2 cm onto a fixed rigid floor 0.8 x 0.2 m, given as `floor` (the keys of its shape).
std::string floor_scene(const std::string& integrator, const std::string& floor) {
  return R"([simulation]
dimension = 2
end_time = 0.08
integrator = ")" +
         integrator + R"("
kernel = "bspline2"
cfl = 0.3
[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [20, 20]
[[materials]]
name = "rubber"
E = 1e6
nu = 0.3
density = 1100.0
[[bodies]]
name = "block"
lo = [0.3, 0.42]
hi = [0.7, 0.62]
[[rigid_bodies]]
name = "floor"
velocity = [0.0, 0.0]
)" + floor +
         R"(
[loads]
gravity = [0.0, -9.81]
)";
}

// The same floor given as a box and as a polygon of the same corners seeds the same points (the box's lattice
// from its lo, the polygon's from the grid's lo: the same points when lo lies on the lattice, to round-off),
// so the run is the same: the floor's reaction and the block's momentum agree to 1e-12 of the block's weight
// (measured: the same bits in both engines).
TEST_P(PolygonRun, RigidPolygonActsAsTheBoxOfItsCorners) {
  const std::string integrator = GetParam();
  const std::filesystem::path dir = scratch("mpm_polygon_floor", integrator);
  std::map<std::string, std::map<std::string, std::vector<double>>> history;
  for (const auto& [name, floor] :
       {std::pair<std::string, std::string>{"box", "lo = [0.1, 0.2]\nhi = [0.9, 0.4]"},
        {"polygon", "shape = \"polygon\"\nvertices = [[0.1, 0.2], [0.9, 0.2], [0.9, 0.4], [0.1, 0.4]]"}}) {
    const std::filesystem::path scene = dir / (name + ".toml");
    std::ofstream(scene) << floor_scene(integrator, floor);
    ASSERT_EQ(run_mpm(scene, "--out " + (dir / name).string(), dir / "log"), 0)
        << testing::slurp(dir / "log");
    history[name] = csv_columns(dir / name / "history.csv");
  }
  const double weight = 1100.0 * 0.4 * 0.2 * 9.81;
  const auto& box = history["box"];
  const auto& polygon = history["polygon"];
  ASSERT_EQ(box.at("time").size(), polygon.at("time").size());
  double largest = 0;
  for (std::size_t k = 0; k < box.at("time").size(); ++k) {
    EXPECT_NEAR(polygon.at("reaction_floor_y")[k], box.at("reaction_floor_y")[k], 1e-12 * weight) << k;
    EXPECT_NEAR(polygon.at("momentum_y")[k], box.at("momentum_y")[k], 1e-12 * weight) << k;
    largest = std::max(largest, std::abs(box.at("reaction_floor_y")[k]));
  }
  EXPECT_GT(largest, 0.5 * weight);  // the block landed and the floor held it
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, PolygonRun, ::testing::Values("usl", "implicit"));

}  // namespace
}  // namespace mpm

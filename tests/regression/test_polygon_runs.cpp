// A polygon body runs in both engines: falling freely under gravity from rest, its momentum is -M g t at every
// step, M the mass of the particles the scene seeds in the outline (rho times their volume).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

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
// 1e-12 over the 0.05 s: a few hundred steps of additions). The body stays clear of the grid's faces (it falls
// 12 mm).
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

INSTANTIATE_TEST_SUITE_P(BothEngines, PolygonRun, ::testing::Values("usl", "implicit"));

}  // namespace
}  // namespace mpm

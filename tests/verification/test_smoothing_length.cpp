// The uGIMP smoothing length l of Steffen et al. 2008, Sec. 4.1 (`simulation.gimp_length`): l = 0 is linear
// MPM, l = l_p is GIMP with the particles' own size, l = h is the quadratic B-spline. Each identity is
// checked by runs of a stretching and rotating block with every integrator, the implicit one included.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "scene_simulation.hpp"
#include "support.hpp"

namespace {
using namespace mpm;

constexpr double h = 0.1;  // the scene's cell size

/// A hypoelastic block in the middle of a 10 x 10 grid of cells h = 0.1 (2 x 2 particles per cell, spacing
/// h/2), stretched and rotated by its initial velocity, crossing cells, run for 0.2 s (about 16 steps).
Scene block(const std::string& integrator, const std::string& kernel) {
  std::ostringstream text;
  text << "[simulation]\nend_time = 0.2\ncfl = 0.5\nintegrator = \"" << integrator << "\"\n"
       << kernel << R"toml(
[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [10, 10]
[[materials]]
name = "m"
model = "hypoelastic"
E = 1e4
nu = 0.3
density = 1000
[[bodies]]
shape = "box"
lo = [0.3, 0.3]
hi = [0.7, 0.7]
velocity = ["0.8 * (x - 0.5) - 0.5 * (y - 0.5)", "0.5 * (x - 0.5)"]
)toml";
  return mpm::testing::scene_from_text("smoothing_length", text.str());
}

/// The particle positions at the end of the scene.
std::vector<Vec<2>> final_positions(const Scene& sc) {
  std::vector<Vec<2>> x;
  mpm::testing::with_scene_simulation<2>(sc, [&](auto& sim) {
    sim.run_until(sc.end_time);
    x = sim.particles().x;
  });
  return x;
}

/// max_p |x_p - y_p|, and the largest distance a particle moved from its start in `a`.
double largest_difference(const std::vector<Vec<2>>& a, const std::vector<Vec<2>>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

class SmoothingLength : public ::testing::TestWithParam<const char*> {};

TEST_P(SmoothingLength, ZeroIsLinearMpm) {
  // l = 0: the reader selects the linear kernel, so the run is linear MPM bit for bit. And the uGIMP kernel
  // tends to it: with l = 1e-6 h the weights differ from the hat only within l/2 of a node (by at most
  // l/(4h)), measured 0 difference in these runs (no particle lands that close to a node line at a step).
  const Scene zero = block(GetParam(), "kernel = \"ugimp\"\ngimp_length = 0.0");
  EXPECT_EQ(zero.kernel, KernelKind::linear);
  const std::vector<Vec<2>> linear = final_positions(block(GetParam(), "kernel = \"linear\""));
  EXPECT_EQ(largest_difference(final_positions(zero), linear), 0.0);
  const std::vector<Vec<2>> tiny =
      final_positions(block(GetParam(), "kernel = \"ugimp\"\ngimp_length = 1e-7"));
  EXPECT_LT(largest_difference(tiny, linear), 1e-6 * h);
}

TEST_P(SmoothingLength, ParticleSizeIsGimp) {
  // l = l_p: the particles' own width (spacing h/2), so the run is the default uGIMP run bit for bit.
  const std::vector<Vec<2>> gimp = final_positions(block(GetParam(), "kernel = \"ugimp\""));
  const std::vector<Vec<2>> l_p =
      final_positions(block(GetParam(), "kernel = \"ugimp\"\ngimp_length = 0.05"));
  EXPECT_EQ(largest_difference(gimp, l_p), 0.0);
}

TEST_P(SmoothingLength, CellSizeIsTheQuadraticBSpline) {
  // l = h: the hat convolved with a top-hat of width h is the quadratic B-spline (Steffen et al. 2008, Eq.
  // (19), Eq. (20)); the two kernels evaluate it by different formulas, so the runs agree to round-off
  // (measured below 1e-15 m after 16 steps), far from the 1e-3 h by which the particle-size run (l = h/2)
  // differs.
  const std::vector<Vec<2>> b2 = final_positions(block(GetParam(), "kernel = \"bspline2\""));
  const std::vector<Vec<2>> l_h = final_positions(block(GetParam(), "kernel = \"ugimp\"\ngimp_length = 0.1"));
  const std::vector<Vec<2>> l_p = final_positions(block(GetParam(), "kernel = \"ugimp\""));
  EXPECT_LT(largest_difference(b2, l_h), 1e-12 * h);
  EXPECT_GT(largest_difference(b2, l_p), 1e-4 * h);
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, SmoothingLength,
                         ::testing::Values("usf", "usl", "cd", "musl", "implicit"));

}  // namespace

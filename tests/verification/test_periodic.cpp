// Periodic face pairs (Steffen et al. 2008, Sec. 4.3: faces = { x-min = "periodic", x-max = "periodic" }):
// the grid's halo adds the contributions its images receive into their owners one period away, and particles
// leaving through one face enter through the other, with every kernel and every integrator.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "scene_simulation.hpp"
#include "support.hpp"

namespace {
using namespace mpm;

constexpr double h = 0.1;       // the cell size
constexpr double length = 1.0;  // the period along x

/// A hypoelastic block 0.4 x 0.4 with its left edge at `left`, translating at 1 m/s along x while it
/// stretches and shears, in a 10 x 10 grid periodic along x and free along y; run for 0.25 s.
Scene block(const std::string& integrator, const std::string& kernel, double left) {
  const double xc = left + 0.2;
  std::ostringstream text;
  text << "[simulation]\nend_time = 0.25\ncfl = 0.4\nintegrator = \"" << integrator << "\"\nkernel = \""
       << kernel << "\"\n"
       << R"toml(
[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [10, 10]
faces = { x-min = "periodic", x-max = "periodic" }
[[materials]]
name = "m"
model = "hypoelastic"
E = 1e4
nu = 0.3
density = 1000
[[bodies]]
shape = "box"
)toml"
       << "lo = [" << left << ", 0.3]\nhi = [" << left + 0.4 << ", 0.7]\n"
       << "velocity = [\"1 + 0.4 * (x - " << xc << ") - 0.3 * (y - 0.5)\", \"0.3 * (x - " << xc << ")\"]\n";
  return mpm::testing::scene_from_text("periodic", text.str());
}

struct Final {
  std::vector<Vec<2>> x, v;  ///< by particle id
};

/// The particles' positions and velocities by id (the explicit engine stores them by tile).
Final by_id(const mpm::ParticleSet<2>& p) {
  Final out{std::vector<Vec<2>>(p.size()), std::vector<Vec<2>>(p.size())};
  for (std::size_t i = 0; i < p.size(); ++i) {
    out.x.at(static_cast<std::size_t>(p.id[i])) = p.x[i];
    out.v.at(static_cast<std::size_t>(p.id[i])) = p.v[i];
  }
  return out;
}

Final run(const Scene& sc) {
  Final out;
  mpm::testing::with_scene_simulation<2>(sc, [&](auto& sim) {
    sim.run_until(sc.end_time);
    out = by_id(sim.particles());
  });
  return out;
}

using Case = std::tuple<const char*, const char*>;  // integrator, kernel
class Periodic : public ::testing::TestWithParam<Case> {};

// A periodic grid maps onto itself under a shift of whole cells, so a block started two cells further along
// must move exactly as the first one, two cells on. The first block (0.2 < x < 0.6) stays clear of the faces
// for the 0.25 m it travels; the second (0.4 < x < 0.8) crosses x = 1 and comes back in at x = 0, so its
// particles and its grid contributions pass through the images. Measured: the two agree to round-off (below
// 6e-15 m); with the images' contributions left out of their owners, the second block ends up to 0.09 m off.
TEST_P(Periodic, ShiftByWholeCellsAcrossTheFaceGivesTheSameMotion) {
  const auto [integrator, kernel] = GetParam();
  const double shift = 2 * h;
  const Final a = run(block(integrator, kernel, 0.2));
  const Final b = run(block(integrator, kernel, 0.2 + shift));
  ASSERT_EQ(a.x.size(), b.x.size());
  double worst_x = 0, worst_v = 0, crossed = 0;
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    Vec<2> d = b.x[i] - a.x[i];
    d[0] -= shift;
    d[0] -= length * std::round(d[0] / length);  // b's particle may have wrapped once
    worst_x = std::max(worst_x, d.norm());
    worst_v = std::max(worst_v, (b.v[i] - a.v[i]).norm());
    if (b.x[i][0] < 0.3) ++crossed;
  }
  std::printf("%s, %s: %g of %zu particles crossed; max |dx| = %.3g m, max |dv| = %.3g m/s\n", integrator,
              kernel, crossed, a.x.size(), worst_x, worst_v);
  EXPECT_GT(crossed, 0);
  EXPECT_LT(worst_x, 1e-10 * h);
  EXPECT_LT(worst_v, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(EveryIntegratorAndKernel, Periodic,
                         ::testing::Combine(::testing::Values("usf", "usl", "cd", "musl", "implicit"),
                                            ::testing::Values("linear", "cpgimp", "bspline2", "bspline3")));

// USL conserves momentum exactly on a grid without constraints, and a periodic pair adds none: the images
// hand their momentum to the owners and back. Measured: sum m v changes by below 1e-15 of its size over the
// run.
TEST(PeriodicMomentum, IsConservedThroughTheFace) {
  for (const char* kernel : {"linear", "cpgimp", "bspline3"}) {
    const Scene sc = block("usl", kernel, 0.4);
    const ParticleSet<2> start = seed_bodies<2>(sc);
    Vec<2> p0 = Vec<2>::Zero();
    for (std::size_t i = 0; i < start.size(); ++i) p0 += start.m[i] * start.v[i];
    with_kernel<2>(sc.kernel, [&]<class K>() {
      Simulation<2, K> sim(make_spec<2>(sc), seed_bodies<2>(sc));
      sim.run_until(sc.end_time);
      Vec<2> p1 = Vec<2>::Zero();
      for (std::size_t i = 0; i < sim.particles().size(); ++i)
        p1 += sim.particles().m[i] * sim.particles().v[i];
      EXPECT_LT((p1 - p0).norm(), 1e-13 * p0.norm()) << kernel;
    });
  }
}

}  // namespace

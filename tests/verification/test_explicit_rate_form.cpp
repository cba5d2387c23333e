// The explicit integrators with the rate-form materials, rigid bodies, plane stress and axisymmetry of Sulsky
// & Kaul 2004: the paper's implicit examples run with `simulation.integrator` set to an explicit integrator
// reach the paper's uniaxial stresses and its explicit upsetting radius.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "support.hpp"

namespace {
namespace fs = std::filesystem;
using namespace mpm;

const fs::path source_dir = fs::path(__FILE__).parent_path().parent_path().parent_path();

using Sim = Simulation<2, LinearKernel>;

Sim load(const std::string& scene, const std::string& integrator, std::vector<std::string> overrides = {}) {
  overrides.push_back("simulation.integrator=\"" + integrator + "\"");
  const Scene sc = read_scene(source_dir / "examples/implicit" / scene, overrides);
  return Sim(make_spec<2>(sc), seed_bodies<2>(sc));
}

using mpm::testing::Spread;

// The rigid body drives the bar's end at v = 0.001 over l = 0.3 (the other end a symmetry plane), so the
// hypoelastic plane-stress uniaxial stress is E v t / l = 33.3 at t = 10 (Sulsky & Kaul 2004, Sec. 3.1.1;
// its 34.5 is the same formula at its plotted t = 10.34). Tolerance: 2%, as for the implicit engine.
class ElasticBar : public ::testing::TestWithParam<const char*> {};

TEST_P(ElasticBar, ReachesTheUniaxialStressAtTen) {
  Sim sim = load("elastic-bar.toml", GetParam());
  sim.run_until(10.0);
  const double expected = 1000 * 0.001 * 10.0 / 0.3;
  Spread sxx;
  double lateral = 0;
  for (const SymTensor<3>& s : sim.particles().state.sigma) {
    sxx.add(s(0, 0));
    lateral = std::max({lateral, std::abs(s(1, 1)), std::abs(s(0, 1)), std::abs(s(2, 2))});
  }
  const double reaction = -sim.rigid_bodies().reactions()[0][0];
  std::printf(
      "%s: sigma_xx in [%.6g, %.6g], expected %.6g; lateral <= %.3g; reaction / 0.3 = %.6g; %lld steps\n",
      GetParam(), sxx.min, sxx.max, expected, lateral, reaction / 0.3, static_cast<long long>(sim.steps()));
  EXPECT_NEAR(sxx.min, expected, 0.02 * expected);
  EXPECT_NEAR(sxx.max, expected, 0.02 * expected);
  EXPECT_LT(lateral, 0.02 * expected);
  // The rigid body pulls with the stress times the cross-section 0.3 (measured 1.3% above it: the reaction
  // also carries the change of momentum of the particles next to the body, the velocity-difference
  // acceleration).
  EXPECT_NEAR(reaction, expected * 0.3, 0.02 * expected * 0.3);
}

INSTANTIATE_TEST_SUITE_P(Explicit, ElasticBar, ::testing::Values("cd", "usl", "usf", "musl"));

// The elastic-plastic bar (Sec. 3.1.2): sigma = (tau0 + c1 eps) / (1 + c1 / E) past yield with eps = v t /
// l, 67.7 at t = 24 (the paper's 68.5 at its plotted 24.3); eps_bar = eps - sigma / E. Tolerance: 2%.
TEST(PlasticBar, FollowsTheBilinearLawAtTwentyFour) {
  Sim sim = load("plastic-bar.toml", "cd");
  sim.run_until(24.0);
  const double eps = 0.001 * 24.0 / 0.3, expected = (6 + 5000 * eps) / (1 + 5000.0 / 1000);
  Spread sxx, plastic;
  const MaterialState& s = sim.particles().state;
  for (std::size_t i = 0; i < s.sigma.size(); ++i) {
    sxx.add(s.sigma[i](0, 0));
    plastic.add(s.eps_bar[i]);
  }
  std::printf("sigma_xx in [%.6g, %.6g], expected %.6g; eps_bar in [%.6g, %.6g], expected %.6g\n", sxx.min,
              sxx.max, expected, plastic.min, plastic.max, eps - expected / 1000);
  EXPECT_NEAR(sxx.min, expected, 0.02 * expected);
  EXPECT_NEAR(sxx.max, expected, 0.02 * expected);
  EXPECT_NEAR(plastic.min, eps - expected / 1000, 0.02 * eps);
  EXPECT_NEAR(plastic.max, eps - expected / 1000, 0.02 * eps);
}

// Upsetting (Sec. 3.2.7): the axisymmetric billet of radius 10 mm pressed by a no-slip rigid platen to 60%
// reduction bulges to a final radius of "approximately 16.5 mm" in the paper's explicit run. Measured 16.66
// mm (the implicit engine's theta = 0 run gives 16.67 mm, docs/implicit.md); asserted within 2% of 16.5.
// 106,000 steps of 600 particles: one thread, as threads gain nothing at this size and lose much when ctest
// runs tests side by side.
TEST(Upsetting, BulgesToTheExplicitRadius) {
  set_num_threads(1);
  Sim sim = load("upsetting.toml", "cd");
  sim.run_until(9.0e-3);
  double radius = 0;
  for (const Vec<2>& x : sim.particles().x) radius = std::max(radius, x[0]);
  double plastic = 0;
  for (double e : sim.particles().state.eps_bar) plastic = std::max(plastic, e);
  std::printf("final radius %.4f mm, largest eps_bar %.3f, %lld steps\n", 1e3 * radius, plastic,
              static_cast<long long>(sim.steps()));
  EXPECT_NEAR(1e3 * radius, 16.5, 0.02 * 16.5);
}

}  // namespace

// The bar of Sulsky & Kaul 2004, Secs 3.1.1-3.1.2, beyond the examples as shipped: the elastic bar with the
// paper's no-slip end, and the elastic-plastic bar run to t = 100 (33% strain). Each test asserts the
// measured cause of a departure from uniaxial stress, so docs/implicit.md can say why instead of "not
// explained".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "support.hpp"

namespace {
namespace fs = std::filesystem;
using namespace mpm;
using mpm::testing::Spread;

const fs::path examples = fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/implicit";
constexpr double h = 0.1;  // the bars' cell size

/// Runs an example scene (with overrides) to its end time with kernel K; calls `look` with the finished run.
template <class K, class Look>
void run(const std::string& scene, const std::vector<std::string>& overrides, Look&& look) {
  const Scene sc = read_scene(examples / scene, overrides);
  ImplicitSimulation<2, K> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  sim.run_until(sc.end_time);
  ASSERT_NEAR(sim.time(), sc.end_time, 1e-9);
  look(sim);
}

// The paper's no-slip right end (Sec. 3.1.1) instead of the example's roller. A clamp holds the end's width
// while the rest of the bar contracts laterally (nu = 0.3, plane stress), so the stress near it is 2-D and
// sigma_xx spreads about E v t / l = 33.33: measured 32.10 to 36.26 (-3.7%, +8.8%). Only Poisson's ratio
// couples the clamp to sigma_xx: with nu = 0 the same clamped bar is uniaxial to the solver's tolerance
// (measured |sigma_xx - 33.33| < 2e-5), as it is with the roller at nu = 0.3. The example keeps the roller,
// the end for which Sulsky & Kaul 2004, Eq. (3.1.1) (uniaxial stress) is the exact answer.
TEST(ElasticBarNoSlip, ClampRestrainsPoissonContractionAndOnlyThat) {
  const double expected = 1000 * 0.001 * 10 / 0.3;  // Sulsky & Kaul 2004, Eq. (3.1.1)
  for (const char* nu : {"0.3", "0.0"})
    for (const char* end : {"\"fixed\"", "\"symmetry\""})
      run<LinearKernel>(
          "elastic-bar.toml",
          {std::string("materials.0.nu=") + nu, std::string("grid.faces={x-max=") + end + "}"},
          [&](const auto& sim) {
            Spread sxx;
            for (const SymTensor<3>& s : sim.state().sigma) sxx.add(s(0, 0));
            std::printf("nu = %s, x-max = %s: sigma_xx in [%.6f, %.6f]\n", nu, end, sxx.min, sxx.max);
            const bool clamp_matters = std::string(nu) == "0.3" && std::string(end) == "\"fixed\"";
            if (clamp_matters) {
              EXPECT_LT(sxx.min, 0.97 * expected);
              EXPECT_GT(sxx.max, 1.08 * expected);
            } else {
              EXPECT_NEAR(sxx.min, expected, 1e-4 * expected);
              EXPECT_NEAR(sxx.max, expected, 1e-4 * expected);
            }
          });
}

// The elastic-plastic bar at t = 100 with the example's linear kernel. Two columns have crossed into new
// cells, so the cells hold 6, 12, 6 and 12 particles. With linear shape functions the x-force on a free node
// is (sum over the cell to its right of sigma_xx V - the same over the cell to its left) / h, summed over the
// node column, so quasi-static equilibrium makes sum sigma_xx V the same in every cell: a cell holding twice
// the particles holds half the stress. Measured: the four cell sums agree to 1e-4 (4.8347-4.8351) while the
// particles range from 95 to 298. In a hardening material the particles of the crowded cells unload
// elastically and stop straining, so no later step can even the stress out. This is the O(1) quadrature error
// of linear MPM under cell crossing (Steffen et al. 2008, Sec. 4.2).
TEST(PlasticBarAtOneHundred, LinearMpmEqualisesSigmaVolumePerCellNotStress) {
  run<LinearKernel>("plastic-bar.toml", {"simulation.end_time=100"}, [](const auto& sim) {
    const auto& p = sim.particles();
    std::vector<double> cell_sum(7, 0.0);
    std::vector<int> count(7, 0);
    Spread sxx;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const int c = static_cast<int>(std::floor(p.x[i][0] / h));
      cell_sum[c] += sim.state().sigma[i](0, 0) * p.V[i];
      ++count[c];
      sxx.add(sim.state().sigma[i](0, 0));
    }
    Spread sums;
    for (int c = 3; c < 7; ++c) {
      std::printf("cell %d: %d particles, sum sigma_xx V = %.6f\n", c, count[c], cell_sum[c]);
      sums.add(cell_sum[c]);
    }
    std::printf("sigma_xx in [%.2f, %.2f]\n", sxx.min, sxx.max);
    EXPECT_EQ(count[3] + count[4] + count[5] + count[6], static_cast<int>(p.size()));
    EXPECT_LT(sums.max - sums.min, 1e-3 * sums.max);  // measured 8e-5: inertia and the Newton tolerance 1e-6
    EXPECT_GT(sxx.max / sxx.min, 2.5);                // measured 3.1
  });
}

// The same bar with cpGIMP, whose particle domains tile the bar as it stretches, so a uniform stress is in
// equilibrium and every column away from the puller is uniaxial: measured 269.5-288.3 against 278.8, the
// hardening law at eps = v t / l = 1/3 (Sulsky & Kaul 2004, Eq. (2.1.19)). What stays is the grip. The puller
// prescribes its velocity on every node it touches, and its GIMP support reaches one cell beyond its edge:
// the node x = 0.4 moves with it throughout, so the strained gauge is the fixed interval 0.4 < x < 0.7,
// straining at v / 0.3 (hence eps = v t / 0.3, not the ln(4/3) of a bar whose every part stretches), and bar
// material dragged past x = 0.4 into the cell between the puller's edge and that node stops straining. The
// first column does so from the start (64.7-70.5 at t = 100), the second once it crosses (241.2-245.9). This
// holds for any kernel: a particle whose stencil holds only prescribed nodes has zero velocity gradient, and
// a grip that moves through the grid always drags material into such a cell. So no kernel makes every
// particle of this example uniaxial at t = 100; cpGIMP makes every particle outside the grip's cell so.
TEST(PlasticBarAtOneHundred, CpGimpIsUniaxialOutsideTheGripCell) {
  run<GimpKernel>("plastic-bar.toml", {"simulation.end_time=100", "simulation.kernel=\"cpgimp\""},
                  [](const auto& sim) {
                    const auto& p = sim.particles();
                    const double expected = (6 + 5000.0 / 3) / (1 + 5000.0 / 1000);
                    Spread gauge, grip;
                    for (std::size_t i = 0; i < p.size(); ++i)
                      (p.x[i][0] - p.half_length(i)[0] > 0.4 ? gauge : grip).add(sim.state().sigma[i](0, 0));
                    std::printf("gauge: sigma_xx in [%.2f, %.2f]; grip cell: [%.2f, %.2f]; expected %.2f\n",
                                gauge.min, gauge.max, grip.min, grip.max, expected);
                    EXPECT_NEAR(gauge.min, expected, 0.05 * expected);
                    EXPECT_NEAR(gauge.max, expected, 0.05 * expected);
                    EXPECT_LT(grip.min, 0.3 * expected);  // measured 64.7: the first column
                    EXPECT_LT(grip.max, 0.9 * expected);  // measured 245.9: the second column
                  });
}

}  // namespace

namespace {
const std::vector<std::string> fast = {"implicit.step_factor=100", "implicit.start_factor=100"};  // 100x c
const std::vector<std::string> tension = {"simulation.end_time=225"};  // 75% strain
// Plane-strain compression into one column (reached at t = 200) widens the bar past the example's grid: a
// grid 1.5 tall, a rigid body as tall.
const std::vector<std::string> compression = {"grid.lo=[0.0,-0.5]",
                                              "grid.hi=[0.7,1.0]",
                                              "grid.cells=[7,15]",
                                              "rigid_bodies.0.lo=[0.3,-0.5]",
                                              "rigid_bodies.0.hi=[0.4,1.0]",
                                              "rigid_bodies.0.velocity=[0.001,0.0]",
                                              "simulation.geometry=\"plane-strain\""};
const std::string projected = "implicit.positions=\"projected-velocity\"";

std::vector<std::string> joined(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// How far the particles' positions have drifted from the deformation they record: over the pairs of
/// particles seeded side by side (|X_j - X_i| = 0.05, half a cell), the median of |(x_j - x_i) - (F_i +
/// F_j)/2 (X_j - X_i)| / |X_j - X_i|. Moving with the field whose gradient strains them keeps it at the
/// discretisation's level.
template <class Sim>
double median_drift(const Sim& sim) {
  const auto& p = sim.particles();
  std::vector<double> drift;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const Vec<2> dX = p.X[j] - p.X[i];
      if (dX.norm() > 0.0501) continue;
      drift.push_back(((p.x[j] - p.x[i]) - 0.5 * (p.F[i] + p.F[j]) * dX).norm() / dX.norm());
    }
  if (drift.empty()) return std::nan("");  // no pair seeded side by side
  std::nth_element(drift.begin(), drift.begin() + drift.size() / 2, drift.end());
  return drift[drift.size() / 2];
}

// Sulsky & Kaul 2004, Sec. 3.1.2: "tension in the bar under the assumption of plane stress ... is successful
// up to a strain of 75%", with Newton-CG (velocity formulation), and Sec. 3.2.6: "Newton-GMRES also succeeds
// in completing all of the variations". Ours: Newton-CG at 100x reaches t = 225 (75% strain) with the
// particles still spanning the gauge (measured x from 0.225 to 0.660). Newton-GMRES in the momentum
// formulation, moving the particles by Sulsky & Kaul 2004, Eq. (3.2.5) as the paper prints it, throws a
// particle out of the grid at t = 180.1 (60% strain); moving them with the projected velocity v^L of Sulsky &
// Kaul 2004, Eq. (3.2.7) it reaches t = 225 as Newton-CG does.
TEST(PlasticBarVariants, PlaneStressTensionToSeventyFivePercentCompletes) {
  const auto spans_the_gauge = [](const auto& sim) {
    Spread x;
    for (const Vec<2>& p : sim.particles().x) x.add(p[0]);
    EXPECT_LT(x.min, 0.3);
    EXPECT_GT(x.max, 0.6);
  };
  run<LinearKernel>(
      "plastic-bar.toml",
      joined(joined(tension, fast), {"implicit.solver=\"newton-cg\"", "implicit.formulation=\"velocity\""}),
      spans_the_gauge);
  run<LinearKernel>("plastic-bar.toml", joined(joined(tension, fast), {projected}), spans_the_gauge);
  const Scene sc = read_scene(examples / "plastic-bar.toml", joined(tension, fast));
  ImplicitSimulation<2, LinearKernel> gmres(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  try {
    gmres.run_until(sc.end_time);
    ADD_FAILURE() << "Newton-GMRES with Eq. (3.2.5) reached t = 225";
  } catch (const SimulationFailure& e) {
    EXPECT_NE(std::string(e.what()).find("would leave the grid"), std::string::npos) << e.what();
    EXPECT_GT(gmres.time(), 170.0);
  }
}

// Why Sulsky & Kaul 2004, Eq. (3.2.5) fails. The stress follows the strain increments of v^L, the velocity
// projected from the particles' updated velocities (Sulsky & Kaul 2004, Eq. (3.2.7)); Sulsky & Kaul 2004,
// Eq. (3.2.5) moves the particles with sum_i P_i^L N_i / m_i, which differs from v^L most at the lightly
// covered nodes the paper writes it for. Nothing resists that difference, so the particles' positions drift
// from the deformation gradients they carry. Measured (Newton-GMRES 100x c), the median drift between
// neighbours: tension at t = 100, 0.0235 with the paper's update against 0.0006 with v^L; plane-strain
// compression at t = 80 (before the paper's update fails at t = 91.8), 0.0254 against 0.0021. The drift grows
// until a particle leaves the bar (0.15 at t = 140 in tension). The bounds leave a factor of 2.9 or more to
// each measured value.
TEST(PlasticBarVariants, MomentumPositionsDriftFromTheDeformationTheParticlesRecord) {
  const std::vector<std::string> pulled;  // the example's bar is pulled
  for (const auto& [name, variant, t] :
       {std::tuple{"tension", pulled, "100"}, std::tuple{"compression", compression, "80"}}) {
    double drift[2] = {std::nan(""), std::nan("")};
    for (int moves_with_v = 0; moves_with_v < 2; ++moves_with_v) {
      std::vector<std::string> sets =
          joined(joined(variant, fast), {std::string("simulation.end_time=") + t});
      if (moves_with_v) sets.push_back(projected);
      run<LinearKernel>("plastic-bar.toml", sets,
                        [&](const auto& sim) { drift[moves_with_v] = median_drift(sim); });
    }
    std::printf("%s at t = %s: median drift %.4f with positions by Eq. 3.2.5, %.4f with v^L\n", name, t,
                drift[0], drift[1]);
    EXPECT_GT(drift[0], 0.008);
    EXPECT_LT(drift[1], 0.006);
  }
}
}  // namespace

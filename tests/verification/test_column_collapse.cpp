// The planar granular column collapse of examples/geomechanics/column-collapse.toml against the experiments
// of Lube et al. (2005): for aspect ratios a below about 1.8 the run-out is (L - L0) / L0 = 1.2 a, and below
// about 1.15 the final height at the wall is the initial one, H = a L0. Mohr-Coulomb sand (phi = 30 degrees,
// c = 0, no dilatancy) on a floor of friction 0.5, h = L0 / 20.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../regression/support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const fs::path example = fs::path(__FILE__).parent_path().parent_path().parent_path() /
                         "examples/geomechanics/column-collapse.toml";

constexpr double L0 = 0.2, h = L0 / 20, s = h / 2;  // the example's width, cell and particle spacing [m]

/// The deposit at rest: its run-out (L - L0) / L0, L the right edge of the farthest cell column (width h)
/// whose particles reach higher than h (three particle layers and more: the scattered grains beyond are not
/// the deposit), and its height at the wall H / L0 (the top particle within h of the wall, plus s / 2); the
/// kinetic energy left against the work gravity did, and summary.json's bounded_domains (null unless cpGIMP).
struct Deposit {
  double runout, height, kinetic_left;
  nlohmann::json bounded;
};
Deposit collapse(const std::string& name, double a, const std::string& end_time,
                 const std::string& args = "") {
  const fs::path dir = scratch("collapse", name);
  const int status =
      run_mpm(example,
              "--out " + (dir / "out").string() + " --set constants.a=" + std::to_string(a) +
                  " --set simulation.end_time=" + end_time + " --set output.every=" + end_time + " " + args,
              dir / "log.txt");
  EXPECT_EQ(status, 0) << slurp(dir / "log.txt");
  const std::vector<double> x = vtp_array(dir / "out/particles_0001.vtp", "");
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  fs::remove_all(dir);
  std::vector<double> top(200, 0.0);
  for (std::size_t i = 0; 3 * i < x.size(); ++i) {
    const auto column = static_cast<std::size_t>(x[3 * i] / h);
    if (column < top.size()) top[column] = std::max(top[column], x[3 * i + 1]);
  }
  std::size_t last = 0;
  for (std::size_t k = 0; k < top.size(); ++k)
    if (top[k] > h) last = k;
  const nlohmann::json& energy = summary["energy"];
  return {(static_cast<double>(last + 1) * h - L0) / L0, (top[0] + s / 2) / L0,
          energy["kinetic"].get<double>() / energy["external_work"].get<double>(),
          summary.value("bounded_domains", nlohmann::json())};
}

TEST(ColumnCollapse, AShortColumnRunsOutAsTheExperimentsAndKeepsItsHeight) {
  // a = 0.5, at rest by t = 0.5 s: measured run-out 0.60 (Lube et al. 2005: 1.2 a = 0.60) and height 0.500 L0
  // (= a). Asserted: the run-out to 10% (one cell of the run-out is 0.05 L0, 8% of it) and the height to 2%.
  const Deposit d = collapse("a05", 0.5, "0.5");
  EXPECT_NEAR(d.runout, 1.2 * 0.5, 0.1 * 1.2 * 0.5);
  EXPECT_NEAR(d.height, 0.5, 0.02 * 0.5);
}

TEST(ColumnCollapse, ASquareColumnKeepsItsHeightAndRunsOutFurtherThanTheExperiments) {
  // a = 1, at rest by t = 0.75 s: measured height 0.973 L0 (Lube et al. 2005: a = 1 below a = 1.15), asserted
  // to 5%. Measured run-out 1.65 against 1.2 a = 1.2: 37% further, and the excess grows with a (52% at a = 2,
  // scripts/column-collapse.py). With phi = 35 degrees and a floor of friction 0.7 the run-out is 1.30
  // (script output): the floor's friction and the friction angle, which the papers do not give as
  // Mohr-Coulomb parameters, set most of it. Asserted: further than the experiments, by less than half.
  const Deposit d = collapse("a1", 1.0, "0.75");
  EXPECT_NEAR(d.height, 1.0, 0.05);
  EXPECT_GT(d.runout, 1.2);
  EXPECT_LT(d.runout, 1.5 * 1.2);
}

TEST(ColumnCollapse, TheDefaultKernelRunsBothColumnsToRestWithBoundedDomains) {
  // With kernel = "cpgimp" (the default) both columns stopped at t = 0.091 s (a = 0.5) and 0.089 s (a = 1),
  // a particle's half-length l0 F_xx past h/2. Bounded to [l0/4, h/2] (docs/kernels.md) from then on, they
  // run to rest. Measured: first bounded after steps 1599 (t = 0.0906 s) and 1573 (0.0895 s), at most 162 and
  // 701 particles at once; deposits 0.65 and 1.65 (uGIMP 0.60 and 1.65), heights 0.500 and 0.987 (uGIMP 0.500
  // and 0.976); the kinetic energy left 3.3e-3 and 2.1e-3 of gravity's work. Asserted: the same bounds as the
  // uGIMP runs above, and kinetic energy below 1% of the work.
  const Deposit a05 = collapse("a05-cpgimp", 0.5, "0.5", "--set simulation.kernel=cpgimp");
  EXPECT_NEAR(a05.runout, 1.2 * 0.5, 0.1 * 1.2 * 0.5);
  EXPECT_NEAR(a05.height, 0.5, 0.02 * 0.5);
  const Deposit a1 = collapse("a1-cpgimp", 1.0, "0.75", "--set simulation.kernel=cpgimp");
  EXPECT_NEAR(a1.height, 1.0, 0.05);
  EXPECT_GT(a1.runout, 1.2);
  EXPECT_LT(a1.runout, 1.5 * 1.2);
  for (const Deposit* d : {&a05, &a1}) {
    EXPECT_LT(d->kinetic_left, 0.01);
    ASSERT_TRUE(d->bounded.is_object());
    EXPECT_GT(d->bounded["first_time"].get<double>(), 0.08);
    EXPECT_LT(d->bounded["first_time"].get<double>(), 0.1);
    EXPECT_GT(d->bounded["most_particles"].get<int>(), 0);
  }
}

}  // namespace

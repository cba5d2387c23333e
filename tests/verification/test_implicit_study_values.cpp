// The numbers docs/implicit.md reports for the examples of Sulsky & Kaul 2004 (scripts/implicit-study.py),
// run here at the sizes the suite affords: the cost rows of Tables 4 and 5 (steps, Newton and GMRES
// iterations), the colliding disks' energy kept, and the upsetting's final radius and platen load at 1000x
// and 10000x.
//
// Tolerances: the steps of the bars and disks are set by the step control alone and must match exactly.
// Counts and results carry the rounding of the transfers, which differs with the vector width of the machine
// (AVX-512 or AVX2) and is amplified by the solver tolerances: between the study of 2026-11-22 and today's,
// whose code differs in the order of the transfer sums (among other changes), the upsetting's load at 1000x
// moved from 841 to 825 kN (2%), the disks' energy kept at 100x from 0.1195 to 0.1213 (1.5%) and a GMRES
// count by 2. So counts are held to 10%, those results to 5%, the upsetting's steps (which retries can
// change) to 5% and its radius to 0.1 mm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace {
namespace fs = std::filesystem;
using namespace mpm;

const fs::path examples = fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/implicit";
constexpr double pi = 3.14159265358979323846;

std::vector<std::string> factors(int step, int start) {
  return {"implicit.step_factor=" + std::to_string(step), "implicit.start_factor=" + std::to_string(start)};
}

struct CostRow {
  const char* scene;
  const char* run;
  int step_factor, start_factor;
  std::int64_t steps, newton, krylov;  // docs/implicit.md
  bool newton_cg = false;   ///< the paper's Newton-CG runs (Tables 1 and 3) instead of Newton-GMRES
  bool paper_step = false;  ///< Sec. 6 of the doc: cfl 0.5802 makes the explicit step the paper's 0.005
};

class CostTable : public ::testing::TestWithParam<CostRow> {};

TEST_P(CostTable, CountsAreTheDocs) {
  const CostRow& c = GetParam();
  std::vector<std::string> overrides = factors(c.step_factor, c.start_factor);
  if (c.newton_cg)
    for (const char* o : {"implicit.solver=\"newton-cg\"", "implicit.formulation=\"velocity\"",
                          "implicit.residual=\"unscaled\""})
      overrides.emplace_back(o);
  if (c.paper_step) overrides.emplace_back("simulation.cfl=0.5802");
  const Scene sc = read_scene(examples / c.scene, overrides);
  ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  sim.run_until(sc.end_time);
  const auto& n = sim.counters();
  std::printf("%s %s: %lld steps, %lld Newton, %lld Krylov\n", c.scene, c.run,
              static_cast<long long>(sim.steps()), static_cast<long long>(n.newton_iterations),
              static_cast<long long>(n.krylov_iterations));
  EXPECT_EQ(sim.steps(), c.steps);
  EXPECT_NEAR(static_cast<double>(n.newton_iterations), static_cast<double>(c.newton),
              0.1 * static_cast<double>(c.newton));
  EXPECT_NEAR(static_cast<double>(n.krylov_iterations), static_cast<double>(c.krylov),
              0.1 * static_cast<double>(c.krylov));
}

// Table 4 (elastic bar) and Table 5 (elastic-plastic bar): every implicit row of the doc; Tables 1 and 3
// (Newton-CG): the rows at 1x a and 100x c; Sec. 6: the 100x c runs at the paper's step, whose steps and
// Newton iterations (20 and 21; 48 and 49) are within 10% of the paper's (22 and 21; 49 and 48) while GMRES
// takes 2.5x and 1.9x the paper's (106 against 42; 355 against 186).
INSTANTIATE_TEST_SUITE_P(
    Tables1And3And4And5, CostTable,
    ::testing::Values(CostRow{"elastic-bar.toml", "1x a", 1, 1, 2321, 203, 518},
                      CostRow{"elastic-bar.toml", "10x a", 10, 1, 241, 111, 544},
                      CostRow{"elastic-bar.toml", "10x b", 10, 10, 233, 104, 508},
                      CostRow{"elastic-bar.toml", "100x a", 100, 1, 44, 41, 199},
                      CostRow{"elastic-bar.toml", "100x b", 100, 10, 32, 32, 158},
                      CostRow{"elastic-bar.toml", "100x c", 100, 100, 24, 25, 125},
                      CostRow{"plastic-bar.toml", "1x a", 1, 1, 5570, 684, 2549},
                      CostRow{"plastic-bar.toml", "10x a", 10, 1, 566, 565, 3929},
                      CostRow{"plastic-bar.toml", "10x b", 10, 10, 557, 557, 3888},
                      CostRow{"plastic-bar.toml", "100x a", 100, 1, 77, 77, 532},
                      CostRow{"plastic-bar.toml", "100x b", 100, 10, 64, 64, 460},
                      CostRow{"plastic-bar.toml", "100x c", 100, 100, 56, 57, 416},
                      CostRow{"elastic-bar.toml", "CG 1x a", 1, 1, 2321, 124, 825, true},
                      CostRow{"elastic-bar.toml", "CG 100x c", 100, 100, 24, 25, 202, true},
                      CostRow{"plastic-bar.toml", "CG 1x a", 1, 1, 5570, 308, 2683, true},
                      CostRow{"plastic-bar.toml", "CG 100x c", 100, 100, 56, 64, 733, true},
                      CostRow{"elastic-bar.toml", "100x c paper step", 100, 100, 20, 21, 106, false, true},
                      CostRow{"plastic-bar.toml", "100x c paper step", 100, 100, 48, 49, 355, false, true}),
    [](const auto& test) {
      std::string n = std::string(test.param.scene).substr(0, 7) + "_" + test.param.run;
      for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return n;
    });

// Colliding disks (Table 2's cases, Fig. 3): the total energy kept at t = 150 falls with the step, as the
// paper's curves show. Doc: 0.8699 at 10x a, 0.1517 at 100x a, with 706 and 91 steps.
TEST(CollidingDisks, EnergyKeptFallsWithTheStepAsDocumented) {
  struct Case {
    int step_factor;
    std::int64_t steps;
    double kept;
  };
  for (const Case& c : {Case{10, 706, 0.8699}, Case{100, 91, 0.1517}}) {
    const Scene sc = read_scene(examples / "colliding-disks.toml", factors(c.step_factor, 1));
    ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
    auto energy = [&] {
      double e = 0;
      const ParticleSet<2>& p = sim.particles();
      for (std::size_t i = 0; i < p.size(); ++i)
        e += 0.5 * p.m[i] * p.v[i].squaredNorm() + sim.state().energy[i];
      return e;
    };
    const double start = energy();
    sim.run_until(sc.end_time);
    const double kept = energy() / start;
    std::printf("%dx a: %lld steps, energy kept %.4f\n", c.step_factor, static_cast<long long>(sim.steps()),
                kept);
    EXPECT_EQ(sim.steps(), c.steps);
    EXPECT_NEAR(kept, c.kept, 0.05 * c.kept);
  }
}

// Colliding disks (Sec. 3.1.1, Fig. 2b and Table 2): with the disks in the corners, centres (0.25, 0.25) and
// (0.75, 0.75), the strain energy peaks at t = 73 (doc: 72.96), near the impact the paper pictures at t = 75.
// Table 2's setting (Newton-CG, velocity formulation, epsilon = 1e-5 on the unscaled residual) at the paper's
// explicit step 0.02438 takes the paper's steps (doc: 6153, paper 6151) and CG iterations per Newton
// iteration (doc: 29.3, paper 12524 / 428 = 29.3), within 5%; the Newton count (doc: 1051) is 2.5x the
// paper's 428.
TEST(CollidingDisks, ImpactAndTable2CountsAtThePapersStep) {
  std::vector<std::string> sets = factors(1, 1);
  sets.insert(sets.end(),
              {"simulation.cfl=0.5664", "implicit.formulation=\"velocity\"", "implicit.solver=\"newton-cg\"",
               "implicit.residual=\"unscaled\"", "implicit.newton_tolerance=1e-5"});
  const Scene sc = read_scene(examples / "colliding-disks.toml", sets);
  ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  double peak = 0, peak_time = 0;
  while (sim.time() < sc.end_time * (1 - 1e-14)) {
    sim.step(sc.end_time - sim.time());
    double strain = 0;
    for (double e : sim.state().energy) strain += e;
    if (strain > peak) peak = strain, peak_time = sim.time();
  }
  const ImplicitCounters& n = sim.counters();
  const double per = static_cast<double>(n.krylov_iterations) / static_cast<double>(n.newton_iterations);
  std::printf("dt %.5f, %lld steps, %lld Newton, %lld CG (%.2f per Newton), strain energy peak at t = %.2f\n",
              sim.explicit_dt(), static_cast<long long>(sim.steps()),
              static_cast<long long>(n.newton_iterations), static_cast<long long>(n.krylov_iterations), per,
              peak_time);
  EXPECT_NEAR(sim.explicit_dt(), 0.02438, 1e-4);
  EXPECT_NEAR(static_cast<double>(sim.steps()), 6151, 0.05 * 6151);
  EXPECT_NEAR(per, 12524.0 / 428, 0.05 * 12524.0 / 428);
  EXPECT_NEAR(static_cast<double>(n.newton_iterations), 1051, 0.05 * 1051);
  EXPECT_NEAR(peak_time, 75, 3);
}

// Upsetting (Table 6, Figs 10 and 12a): steps, Newton and GMRES iterations (to 10%, as the bars' cost table),
// final radius (largest particle r) and platen load -2 pi R_y at the last step. Doc: 108 steps, 461 Newton,
// 18472 GMRES, 16.66 mm and 825 kN at 1000x; 16 steps, 110 Newton, 5819 GMRES, 16.66 mm and 930 kN at 10000x.
// The paper: 98 and 16 steps, 298 and 58 Newton, 5344 and 1040 GMRES, about 16.5 mm and 1050 kN. Measured
// 2026-11-29, after the implicit step took the explicit pass's lane formula for F (rounding differently in
// the last bit): 113 steps, 494 Newton, 20016 GMRES, 16.69 mm and 854.5 kN at 1000x; 16, 110, 5817, 16.66 mm
// and 930.1 kN at 10000x.
TEST(Upsetting, RadiusAndLoadAreTheDocs) {
  struct Case {
    int factor;
    std::int64_t steps, newton, gmres;
    double radius_mm, load_kn;
  };
  for (const Case& c : {Case{1000, 108, 461, 18472, 16.66, 825}, Case{10000, 16, 110, 5819, 16.66, 930}}) {
    const Scene sc = read_scene(examples / "upsetting.toml", factors(c.factor, c.factor));
    ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
    sim.run_until(sc.end_time);
    double radius = 0;
    for (const Vec<2>& x : sim.particles().x) radius = std::max(radius, x[0]);
    const double load = -2 * pi * sim.rigid_reactions()[0][1];
    const ImplicitCounters& n = sim.counters();
    std::printf("%dx: %lld steps, %lld Newton, %lld GMRES, radius %.3f mm, load %.1f kN\n", c.factor,
                static_cast<long long>(sim.steps()), static_cast<long long>(n.newton_iterations),
                static_cast<long long>(n.krylov_iterations), radius * 1e3, load / 1e3);
    EXPECT_NEAR(static_cast<double>(sim.steps()), static_cast<double>(c.steps),
                0.05 * static_cast<double>(c.steps));
    EXPECT_NEAR(static_cast<double>(n.newton_iterations), static_cast<double>(c.newton),
                0.1 * static_cast<double>(c.newton));
    EXPECT_NEAR(static_cast<double>(n.krylov_iterations), static_cast<double>(c.gmres),
                0.1 * static_cast<double>(c.gmres));
    EXPECT_NEAR(radius * 1e3, c.radius_mm, 0.1);
    EXPECT_NEAR(load / 1e3, c.load_kn, 0.05 * c.load_kn);
  }
}

}  // namespace

namespace {
// Upsetting (Fig. 11): the paper's largest plastic strain is at the upper right, "a singularity forming as
// the material folds against the platen". With the frozen-Jacobian preconditioner (the same answers, faster):
// at the fold (r > 8 mm, within 1.5 mm below the platen face) and at the mid-plane centre (r < 5 mm, z < 2
// mm), measured 1.500 and 1.776 on the 1 mm mesh at 1000x, 1.861 and 1.848 on the 0.5 mm mesh at 2000x (doc,
// Sec. 4). The fold's grows by 24% with the refinement, a singularity's growth, the centre's by 4%, so that
// the fold holds the maximum on the 0.5 mm mesh as in the paper, and the centre on the 1 mm one.
TEST(Upsetting, LargestPlasticStrainMovesToTheFoldUnderRefinement) {
  double fold[2], centre[2];
  const char* meshes[2][2] = {{"grid.cells=[24,18]", "1000"}, {"grid.cells=[48,36]", "2000"}};
  for (int m = 0; m < 2; ++m) {
    std::vector<std::string> sets = factors(std::stoi(meshes[m][1]), std::stoi(meshes[m][1]));
    sets.insert(sets.end(), {meshes[m][0], "implicit.preconditioner=\"frozen-jacobian\""});
    const Scene sc = read_scene(examples / "upsetting.toml", sets);
    ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
    sim.run_until(sc.end_time);
    const double face = 15.0 - sim.time() * 1e3;  // mm
    fold[m] = centre[m] = 0;
    const ParticleSet<2>& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double r = p.x[i][0] * 1e3, z = p.x[i][1] * 1e3, eps = sim.state().eps_bar[i];
      if (r > 8 && z > face - 1.5 && z <= face) fold[m] = std::max(fold[m], eps);
      if (r < 5 && z < 2) centre[m] = std::max(centre[m], eps);
    }
    std::printf("%s: fold %.4f, centre %.4f\n", meshes[m][0], fold[m], centre[m]);
  }
  EXPECT_LT(fold[0], centre[0]);
  EXPECT_GT(fold[1], centre[1]);
  EXPECT_GT(fold[1], 1.15 * fold[0]);
  EXPECT_LT(centre[1], 1.08 * centre[0]);
}
}  // namespace

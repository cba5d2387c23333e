// The Newton-GMRES parameters of Sulsky & Kaul 2004, Sec. 3.2.2: the derivative step h of Eq. (2.4.18)
// against Newton's quadratic convergence (Fig. 5), and the linear parameter gamma and the non-linear epsilon
// against the cost (Figs 6-8), on the elastic-plastic bar.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
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
using Sim = ImplicitSimulation<2, LinearKernel>;

Sim load(const std::vector<std::string>& overrides) {
  const Scene sc = read_scene(examples / "plastic-bar.toml", overrides);
  return Sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
}

struct Convergence {
  int multi = 0;               // steps with two or more Newton iterations
  std::vector<double> ratios;  // each such step's largest ||F_{n+1}|| / ||F_n||^2
  double sxx_min = 0, sxx_max = 0;
  double worst() const { return *std::max_element(ratios.begin(), ratios.end()); }
  double median() const {
    std::vector<double> r = ratios;
    std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2), r.end());
    return r[r.size() / 2];
  }
};

/// Fig. 5's runs: the bar to t = 100 at the explicit step, gamma = 1e-12 (the linear systems solved to
/// round-off), epsilon = 1e-4, and the derivative step h.
Convergence newton_residuals(const std::string& h) {
  Sim sim = load({"simulation.end_time=100", "implicit.linear_tolerance=1e-12",
                  "implicit.newton_tolerance=1e-4", "implicit.derivative_step=" + h, "implicit.step_factor=1",
                  "implicit.start_factor=1", "implicit.restart=200", "implicit.max_krylov=2000"});
  Convergence c;
  while (sim.time() < 100 * (1 - 1e-14)) {
    sim.step(100 - sim.time());
    const std::vector<double>& r = sim.last_residual_norms();
    if (r.size() < 3) continue;
    ++c.multi;
    double worst = 0;
    for (std::size_t k = 0; k + 1 < r.size(); ++k) worst = std::max(worst, r[k + 1] / (r[k] * r[k]));
    c.ratios.push_back(worst);
  }
  Spread sxx;
  for (const SymTensor<3>& s : sim.state().sigma) sxx.add(s(0, 0));
  c.sxx_min = sxx.min;
  c.sxx_max = sxx.max;
  return c;
}

// Fig. 5 (Sec. 3.2.2): with gamma = 1e-12 Newton converges quadratically, ||F_{n+1}|| <= C ||F_n||^2, on the
// steps that need two or more iterations (13 here in every run, 5 in the paper's), for derivative steps from
// 1e-7 to 1e-3: C <= 0.0245 (measured, the same for 1e-7, 1e-6, 1e-5, 1e-4 and 1e-3, median 0.0022 to
// 0.0032). At h = 1e-2 the difference quotient's error shows: C = 0.0545, median 0.0168. The paper loses
// quadratic convergence at the small end instead (some steps at 1e-7, one at 1e-6), which ours does not. The
// stress at t = 100 is the same for every h to 0.01 (the paper: the same curves except at h = 1e-2).
TEST(ImplicitParameters, DerivativeStepFrom1e7To1e3KeepsNewtonQuadratic) {
  const Convergence small = newton_residuals("1e-7"), mid = newton_residuals("1e-5"),
                    large = newton_residuals("1e-2");
  std::printf(
      "steps with two or more iterations: %d, %d, %d; largest C %.4g, %.4g, %.4g; median %.4g, %.4g, %.4g\n",
      small.multi, mid.multi, large.multi, small.worst(), mid.worst(), large.worst(), small.median(),
      mid.median(), large.median());
  ASSERT_EQ(small.multi, 13);
  ASSERT_EQ(mid.multi, 13);
  ASSERT_EQ(large.multi, 13);
  EXPECT_LT(small.worst(), 0.03);
  EXPECT_LT(mid.worst(), 0.03);
  EXPECT_GT(large.worst(), 2 * mid.worst());
  EXPECT_GT(large.median(), 4 * mid.median());
  for (const Convergence* c : {&small, &large}) {
    EXPECT_NEAR(c->sxx_min, mid.sxx_min, 0.01);
    EXPECT_NEAR(c->sxx_max, mid.sxx_max, 0.01);
  }
}

/// Evaluation units (residual evaluations + steps) of the bar to t = 100 at 100 x the explicit step, h =
/// 1e-5.
std::int64_t cost(const std::string& gamma, const std::string& epsilon) {
  Sim sim = load({"simulation.end_time=100", "implicit.step_factor=100", "implicit.start_factor=100",
                  "implicit.linear_tolerance=" + gamma, "implicit.newton_tolerance=" + epsilon});
  sim.run_until(100);
  return sim.counters().residual_evaluations + sim.steps();
}

// Fig. 8 (Sec. 3.2.2) at h = 1e-5: a smaller gamma costs more, at every epsilon from 1e-1 to 1e-4 (measured,
// in evaluation units: 882 < 1358 < 2038 < 2225 at epsilon = 1e-1, 2088 < 2819 < 3986 < 4591 at 1e-4). At
// 1e-6 the loosest gamma needs so many more Newton iterations (693 against 263) that it costs about as much
// as gamma = 1e-6. The paper finds epsilon = 1e-4 "basically the same" cost as 1e-1; ours costs 2.0-2.4x as
// much at this step, and 1e-6 costs less than twice 1e-4 for gamma <= 1e-2, as the paper says, but 2.4x for
// gamma = 1e-1.
TEST(ImplicitParameters, SmallerLinearParameterCostsMore) {
  const char* gammas[] = {"1e-1", "1e-2", "1e-4", "1e-6"};
  double at[3][4];  // evaluation units
  const char* epsilons[] = {"1e-1", "1e-4", "1e-6"};
  for (int e = 0; e < 3; ++e)
    for (int g = 0; g < 4; ++g) at[e][g] = static_cast<double>(cost(gammas[g], epsilons[e]));
  for (int e = 0; e < 3; ++e)
    std::printf("epsilon %s: %.0f %.0f %.0f %.0f\n", epsilons[e], at[e][0], at[e][1], at[e][2], at[e][3]);
  for (int e = 0; e < 2; ++e)
    for (int g = 0; g + 1 < 4; ++g)
      EXPECT_LT(at[e][g], at[e][g + 1]) << "epsilon " << epsilons[e] << ", gamma " << gammas[g];
  for (int g = 0; g < 4; ++g) {
    EXPECT_GT(at[1][g], 1.9 * at[0][g]) << "gamma " << gammas[g];
    EXPECT_LT(at[1][g], 2.5 * at[0][g]) << "gamma " << gammas[g];
    if (g > 0) {
      EXPECT_LT(at[2][g], 2 * at[1][g]) << "gamma " << gammas[g];
    }
  }
  EXPECT_GT(at[2][0], 2 * at[1][0]);
}

// Fig. 9 (Sec. 3.2.3): the paper's bar at the explicit step needs 46 and 15 Newton iterations without a line
// search at two steps where a row of particles or the rigid body crosses into a new element. Ours needs at
// most 2 at every one of its 23,205 steps to t = 100 without it (the same counts as with it: no step
// backtracks), so the bar does not exercise the line search. The upsetting does: at 10000 x the explicit step
// the first step does not converge in 50 Newton iterations without it, and converges with 3 backtracks with
// it (measured: 13 Newton iterations in the two steps to t = 1 ms; without it and with halving allowed, 26
// steps, 10 of them halved, 579 iterations).
TEST(ImplicitParameters, TheBarNeedsNoLineSearchTheUpsettingDoes) {
  Sim bar = load({"simulation.end_time=100", "implicit.step_factor=1", "implicit.start_factor=1",
                  "implicit.line_search=\"off\""});
  int worst = 0;
  while (bar.time() < 100 * (1 - 1e-14)) {
    bar.step(100 - bar.time());
    worst = std::max(worst, bar.last_newton_iterations());
  }
  EXPECT_EQ(bar.steps(), 23205);
  EXPECT_EQ(worst, 2);

  const auto upsetting = [](const char* line_search) {
    const Scene sc =
        read_scene(examples / "upsetting.toml",
                   {"implicit.step_factor=10000", "implicit.start_factor=10000", "implicit.max_retries=0",
                    std::string("implicit.line_search=\"") + line_search + "\""});
    return Sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  };
  Sim with = upsetting("on");
  with.run_until(1e-3);
  EXPECT_EQ(with.steps(), 2);
  EXPECT_EQ(with.counters().backtracks, 3);
  Sim without = upsetting("off");
  EXPECT_THROW(without.step(), SimulationFailure);
  EXPECT_EQ(without.counters().newton_iterations, 50);
}

}  // namespace

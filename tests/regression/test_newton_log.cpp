// `mpm run` with [output] newton_log = "on": newton.csv holds ||F|| at every Newton iterate of every try at a
// step (Sulsky & Kaul 2004, Figs 5 and 9 draw these), consistent with the counts of history.csv, the tries of
// a step whose solve fails included, and a restart continues it bitwise.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "mpm/io/checkpoint.hpp"
#include "support.hpp"

namespace {
namespace fs = std::filesystem;
using mpm::testing::csv_columns;
using mpm::testing::run_mpm;
using mpm::testing::slurp;

const fs::path plastic_bar =
    fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/implicit/plastic-bar.toml";
const std::string logged = " --set output.newton_log=on --set implicit.step_factor=100";

/// The rows of newton.csv at one step.
struct StepRows {
  std::map<int, std::vector<double>> norms;  // by attempt, in iteration order
  std::map<int, double> dt;                  // by attempt
};

std::map<int, StepRows> by_step(const fs::path& file) {
  auto c = csv_columns(file);
  std::map<int, StepRows> out;
  for (std::size_t r = 0; r < c["step"].size(); ++r) {
    StepRows& s = out[static_cast<int>(c["step"][r])];
    const int a = static_cast<int>(c["attempt"][r]);
    EXPECT_EQ(c["iteration"][r], static_cast<double>(s.norms[a].size())) << "row " << r;
    s.norms[a].push_back(c["residual_norm"][r]);
    s.dt[a] = c["dt"][r];
  }
  return out;
}

// Sulsky & Kaul 2004, Sec. 3.2.2: the residual Newton measures is the momentum equation divided by Y dx dy
// dt, Y the Young's modulus. The bar's first step logged both ways: at the initial guess (the same iterate)
// the scaled norm is the unscaled one over E h^2 dt with E = 1000 Pa, h = 0.1 m and the step's dt, to
// round-off (each component is multiplied by the scale before the norm is taken). Asserted to 1e-13 relative.
TEST(NewtonLog, TheScaledResidualIsTheUnscaledOneOverYoungsModulusTimesCellAreaTimesStep) {
  const fs::path dir = mpm::testing::scratch("mpm_newton_log", "scale");
  std::map<std::string, StepRows> first;
  for (const std::string residual : {"scaled", "unscaled"}) {
    ASSERT_EQ(run_mpm(plastic_bar,
                      logged + " --stop-after 1 --set implicit.residual=" + residual + " --out " +
                          (dir / residual).string(),
                      dir / "log"),
              0)
        << slurp(dir / "log");
    first[residual] = by_step(dir / residual / "newton.csv").at(1);
  }
  const double dt = first["scaled"].dt.at(0);
  EXPECT_EQ(dt, first["unscaled"].dt.at(0));
  const double expected = first["unscaled"].norms.at(0).at(0) / (1000.0 * 0.1 * 0.1 * dt);
  EXPECT_NEAR(first["scaled"].norms.at(0).at(0), expected, 1e-13 * expected);
  fs::remove_all(dir);
}

// Every step of the elastic-plastic bar at 100x: the Newton iterations a step's tries logged (rows less one
// per try) are history.csv's newton_iterations increments; the last try ends at or below newton_tolerance =
// 1e-6 and every iterate before it is above (Newton stops at the first below); its dt is the step history.csv
// took.
TEST(NewtonLog, RowsAreTheIteratesHistoryCounts) {
  const fs::path dir = mpm::testing::scratch("mpm_newton_log", "rows");
  ASSERT_EQ(run_mpm(plastic_bar, logged + " --out " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  const auto rows = by_step(dir / "out/newton.csv");
  auto h = csv_columns(dir / "out/history.csv");
  const std::size_t steps = h["step"].size() - 1;
  ASSERT_EQ(rows.size(), steps);
  int newton_steps = 0;
  for (std::size_t s = 1; s <= steps; ++s) {
    const StepRows& r = rows.at(static_cast<int>(s));
    double iterations = 0;
    for (const auto& [attempt, norms] : r.norms) iterations += static_cast<double>(norms.size()) - 1;
    EXPECT_EQ(iterations, h["newton_iterations"][s] - h["newton_iterations"][s - 1]) << "step " << s;
    const std::vector<double>& last = r.norms.rbegin()->second;
    EXPECT_LE(last.back(), 1e-6) << "step " << s;
    for (std::size_t k = 0; k + 1 < last.size(); ++k)
      EXPECT_GT(last[k], 1e-6) << "step " << s << " iterate " << k;
    EXPECT_NEAR(r.dt.rbegin()->second, h["time"][s] - h["time"][s - 1], 1e-12 * h["time"][s]) << "step " << s;
    newton_steps += last.size() > 1;
  }
  EXPECT_GT(newton_steps, 0);
  fs::remove_all(dir);
}

// One Newton iteration allowed and an unreachable tolerance: the first step fails at dt, dt/2 and dt/4 (two
// halvings), and newton.csv logs the three tries of step 1, each with its initial and one Newton iterate.
TEST(NewtonLog, LogsTheTriesOfAStepThatFails) {
  const fs::path dir = mpm::testing::scratch("mpm_newton_log", "fails");
  EXPECT_EQ(run_mpm(plastic_bar,
                    logged +
                        " --set implicit.max_newton=1 --set implicit.max_retries=2 "
                        "--set implicit.newton_tolerance=1e-14 --out " +
                        (dir / "out").string(),
                    dir / "log"),
            1)
      << slurp(dir / "log");
  const auto rows = by_step(dir / "out/newton.csv");
  ASSERT_EQ(rows.size(), 1u);
  const StepRows& r = rows.at(1);
  ASSERT_EQ(r.norms.size(), 3u);
  for (const auto& [attempt, norms] : r.norms) {
    EXPECT_EQ(norms.size(), 2u) << "attempt " << attempt;
    if (attempt > 0) {
      EXPECT_EQ(r.dt.at(attempt), 0.5 * r.dt.at(attempt - 1));
    }
  }
  fs::remove_all(dir);
}

// Stopped after 10 steps and restarted from its checkpoint, the run writes the same newton.csv as one run.
TEST(NewtonLog, RestartContinuesItBitwise) {
  const fs::path dir = mpm::testing::scratch("mpm_newton_log", "restart");
  const std::string one = (dir / "one").string(), two = (dir / "two").string();
  ASSERT_EQ(run_mpm(plastic_bar, logged + " --out " + one, dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(run_mpm(plastic_bar, logged + " --out " + two + " --stop-after 10", dir / "log"), 0)
      << slurp(dir / "log");
  ASSERT_EQ(
      run_mpm(plastic_bar, logged + " --out " + two + " --restart " + two + "/checkpoint.h5", dir / "log"), 0)
      << slurp(dir / "log");
  EXPECT_EQ(slurp(dir / "one/newton.csv"), slurp(dir / "two/newton.csv"));
  EXPECT_GT(slurp(dir / "one/newton.csv").size(), 1000u);
  fs::remove_all(dir);
}

// The bar at the explicit step with the linear systems solved to 1e-12 (Fig. 5's run) needs a second Newton
// iteration first at t = 26.1. With one Newton iteration allowed and no halving the run stops there, its rows
// logged past the checkpoint of the last good step. Restarted from that checkpoint with the default settings,
// the file is cut back to the checkpoint and continued, and ends bitwise equal to the file of one run with
// them.
TEST(NewtonLog, RestartAfterAFailedStepCutsItBackToTheCheckpoint) {
  const fs::path dir = mpm::testing::scratch("mpm_newton_log", "failed");
  const std::string one = (dir / "one").string(), two = (dir / "two").string();
  const std::string fig5 =
      " --set output.newton_log=on --set simulation.end_time=27 --set implicit.linear_tolerance=1e-12 "
      "--set implicit.newton_tolerance=1e-4";
  ASSERT_EQ(run_mpm(plastic_bar, fig5 + " --out " + one, dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(
      run_mpm(plastic_bar, fig5 + " --set implicit.max_newton=1 --set implicit.max_retries=0 --out " + two,
              dir / "log"),
      1)
      << slurp(dir / "log");
  const auto failed = by_step(dir / "two/newton.csv");
  ASSERT_FALSE(failed.empty());
  EXPECT_EQ(failed.rbegin()->second.norms.at(0).size(),
            2u);  // the failed step: the initial guess and one iterate
  // The failed run's last state (issue 46, item 7): the implicit step fails before it touches the particles,
  // so particles_fail.vtp holds the last good state, the checkpoint's, with no particle marked as failed.
  const std::vector<double> marks = mpm::testing::vtp_array(dir / "two/particles_fail.vtp", "failed");
  const std::vector<double> points = mpm::testing::vtp_array(dir / "two/particles_fail.vtp", "");
  const mpm::io::CheckpointData c = mpm::io::read_checkpoint(dir / "two/checkpoint.h5");
  const std::vector<double>& x = c.reals.at("x");
  ASSERT_FALSE(marks.empty());
  ASSERT_EQ(points.size(), 3 * marks.size());
  const std::size_t dim = x.size() / marks.size();
  for (std::size_t i = 0; i < marks.size(); ++i) {
    EXPECT_EQ(marks[i], 0.0);
    for (std::size_t d = 0; d < dim; ++d) EXPECT_EQ(points[3 * i + d], x[dim * i + d]);
  }
  ASSERT_EQ(
      run_mpm(plastic_bar, fig5 + " --out " + two + " --restart " + two + "/checkpoint.h5", dir / "log"), 0)
      << slurp(dir / "log");
  EXPECT_EQ(slurp(dir / "one/newton.csv"), slurp(dir / "two/newton.csv"));
  EXPECT_FALSE(fs::exists(dir / "two/particles_fail.vtp"));  // the run that went on removed it
  fs::remove_all(dir);
}

}  // namespace

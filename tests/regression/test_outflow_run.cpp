// `mpm run` with an outflow face: history.csv and summary.json count what has left, the momentum balance
// closes with it under gravity, and a run checkpointed after particles left restarts bitwise, with either
// engine.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "mpm/io/checkpoint.hpp"
#include "support.hpp"

namespace {
namespace fs = std::filesystem;
using mpm::testing::csv_columns;
using mpm::testing::slurp;
const auto run = mpm::testing::run_mpm;

const std::string scene = mpm::testing::outflow_scene();
constexpr double mass = 80, g = -9.81;

/// An engine, with the settings the test gives it.
struct Engine {
  const char* name;
  const char* settings;
};
class OutflowRun : public ::testing::TestWithParam<Engine> {};

// The momentum in the grid plus what has left grows by g times the mass still in the grid over each step (no
// other force acts), to 1e-12 of the impulse of gravity. The explicit step conserves momentum to round-off;
// the implicit one up to the sum of its residual's components, so its Newton tolerance is tightened to 1e-11
// (measured worst 6.5e-13 of the impulse; 2.7e-8 at the default 1e-5, 5.5e-10 at 1e-9).
TEST_P(OutflowRun, HistoryCountsWhatLeftAndTheMomentumBalanceCloses) {
  const fs::path dir = mpm::testing::scratch("outflow", GetParam().name);
  std::ofstream(dir / "scene.toml") << scene;
  const std::string set = GetParam().settings;
  ASSERT_EQ(run(dir / "scene.toml", set + " --out " + (dir / "one").string(), dir / "log"), 0)
      << slurp(dir / "log");
  auto h = csv_columns(dir / "one/history.csv");
  ASSERT_TRUE(h.count("outflow_mass") && h.count("outflow_energy") && h.count("outflow_momentum_y"));
  const std::vector<double>& t = h["time"];
  double expected = h["momentum_y"][0];
  for (std::size_t k = 1; k < t.size(); ++k) {
    expected += g * (mass - h["outflow_mass"][k - 1]) * (t[k] - t[k - 1]);
    EXPECT_NEAR(h["momentum_y"][k] + h["outflow_momentum_y"][k], expected,
                1e-12 * std::abs(mass * g * t[k]) + 1e-12)
        << "step " << k;
  }
  EXPECT_GT(h["outflow_mass"].back(), 0.5 * mass);
  EXPECT_LT(h["outflow_mass"].back(), mass);
  const nlohmann::json s = nlohmann::json::parse(slurp(dir / "one/summary.json"));
  EXPECT_EQ(s["particles"].get<int>() + s["outflow"]["particles"].get<int>(), 128);
  EXPECT_EQ(s["outflow"]["mass"].get<double>(), h["outflow_mass"].back());
  EXPECT_GT(s["outflow"]["internal_energy"].get<double>(), 0);
  // The particles that stay keep the ids they were seeded with (0 to 127, in order): the last frame lists the
  // remaining ids ascending, and with them the seeded reference positions (x - displacement).
  const std::vector<double> id = mpm::testing::vtp_array(dir / "one/particles_0004.vtp", "id");
  ASSERT_EQ(id.size(), s["particles"].get<std::size_t>());
  ASSERT_EQ(id.size(), mpm::testing::vtp_array(dir / "one/particles_0000.vtp", "id").size() -
                           s["outflow"]["particles"].get<std::size_t>());
  for (std::size_t k = 0; k < id.size(); ++k) {
    EXPECT_EQ(id[k], std::trunc(id[k]));
    if (k > 0) {
      EXPECT_LT(id[k - 1], id[k]);
    }
  }
  const std::vector<double> id0 = mpm::testing::vtp_array(dir / "one/particles_0000.vtp", "id");
  for (std::size_t k = 0; k < id0.size(); ++k) EXPECT_EQ(id0[k], static_cast<double>(k));
  // Seeded 8 x 16 at 0.025 m spacing from (0.1125, 0.0625), row by row: the id gives the reference position.
  const std::vector<double> x = mpm::testing::vtp_array(dir / "one/particles_0004.vtp", "displacement"),
                            pts = mpm::testing::vtp_array(dir / "one/particles_0004.vtp", "");
  for (std::size_t k = 0; k < id.size(); ++k) {
    const int i = static_cast<int>(id[k]);
    EXPECT_NEAR(pts[3 * k] - x[3 * k], 0.1125 + 0.025 * (i % 8), 1e-12);
    EXPECT_NEAR(pts[3 * k + 1] - x[3 * k + 1], 0.0625 + 0.025 * (i / 8), 1e-12);
  }

  // Stopped after a quarter of the particles have left, and restarted: the same bytes as one run.
  const std::string two = (dir / "two").string();
  ASSERT_EQ(run(dir / "scene.toml", set + " --out " + two + " --stop-after 60", dir / "log"), 0)
      << slurp(dir / "log");
  const nlohmann::json stopped = nlohmann::json::parse(slurp(dir / "two/summary.json"));
  EXPECT_GT(stopped["outflow"]["particles"].get<int>(), 0);
  EXPECT_LT(stopped["outflow"]["particles"].get<int>(), s["outflow"]["particles"].get<int>());
  ASSERT_EQ(
      run(dir / "scene.toml", set + " --out " + two + " --restart " + two + "/checkpoint.h5", dir / "log"), 0)
      << slurp(dir / "log");
  EXPECT_EQ(slurp(dir / "one/history.csv"), slurp(dir / "two/history.csv"));
  EXPECT_EQ(slurp(dir / "one/particles_0004.vtp"), slurp(dir / "two/particles_0004.vtp"));
  EXPECT_EQ(s["outflow"], nlohmann::json::parse(slurp(dir / "two/summary.json"))["outflow"]);
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Engines, OutflowRun,
    ::testing::Values(Engine{"explicit", ""},
                      Engine{"implicit",
                             "--set simulation.integrator=implicit --set implicit.newton_tolerance=1e-11"}),
    [](const auto& test) { return std::string(test.param.name); });

// A checkpoint written before outflow faces existed holds no outflow entries: it restarts as one with nothing
// gone, and the run ends bitwise equal to the uninterrupted one.
TEST(OutflowCheckpoint, AnOlderCheckpointWithoutOutflowEntriesRestarts) {
  const fs::path dir = mpm::testing::scratch("outflow", "older_checkpoint");
  std::ofstream(dir / "scene.toml") << scene;
  const std::string floor = "--set 'grid.faces={y-min=\"symmetry\"}' ";
  ASSERT_EQ(run(dir / "scene.toml", floor + "--out " + (dir / "one").string(), dir / "log"), 0)
      << slurp(dir / "log");
  const fs::path two = dir / "two";
  ASSERT_EQ(run(dir / "scene.toml", floor + "--out " + two.string() + " --stop-after 40", dir / "log"), 0)
      << slurp(dir / "log");
  mpm::io::CheckpointData c = mpm::io::read_checkpoint(two / "checkpoint.h5");
  ASSERT_EQ(c.integer_scalars.erase("outflow_particles"), 1u);
  for (const char* k : {"outflow_mass", "outflow_kinetic_energy", "outflow_internal_energy"})
    c.real_scalars.erase(k);
  c.reals.erase("outflow_momentum");
  mpm::io::write_checkpoint(two / "checkpoint.h5", c);
  ASSERT_EQ(
      run(dir / "scene.toml",
          floor + "--out " + two.string() + " --restart " + (two / "checkpoint.h5").string(), dir / "log"),
      0)
      << slurp(dir / "log");
  EXPECT_EQ(slurp(dir / "one/history.csv"), slurp(two / "history.csv"));
  fs::remove_all(dir);
}

}  // namespace

// `mpirun -np N mpm run SCENE` on 1 to 4 ranks (oversubscribed) writes the same history.csv, byte for byte,
// the same summary figures and the same particle fields (by id, to the bit) as one process, with the frames
// as one .pvtp of N pieces listed in particles.pvd. Cases: the colliding-disks example (particles cross
// between ranks; energies and momenta), the 2-D axis-aligned scene (symmetry-plane reactions, body-force
// work, [check] error norms), the upsetting example made explicit (a rigid platen's reaction, von Mises
// state), a block leaving through an outflow face and a bar pulled by a traction. Skipped when the build has
// no MPI.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <vector>

#include "distributed_support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

/// Runs on 1 to 4 ranks and compares them; returns the one-process summary.json (null without MPI).
nlohmann::json expect_same_on_one_to_four_ranks(const std::string& name, const std::string& scene,
                                                const std::string& args) {
  if (std::string(MPM_MPIEXEC).empty()) return {};  // the tests skip themselves
  std::vector<fs::path> dirs;
  for (int ranks = 1; ranks <= 4; ++ranks) {
    const fs::path dir = scratch("distributed_" + name, std::to_string(ranks));
    const int status = run_on(ranks, scene, args + " --out " + dir.string(), dir / "log.txt");
    EXPECT_EQ(status, 0) << ranks << " ranks: " << slurp(dir / "log.txt");
    if (status != 0) return {};
    dirs.push_back(dir);
  }
  const std::string history = slurp(dirs[0] / "history.csv");
  const nlohmann::json one = nlohmann::json::parse(slurp(dirs[0] / "summary.json"));
  const std::vector<std::string> one_frames = frames(dirs[0]);
  EXPECT_GT(one_frames.size(), 1u);
  if (one_frames.size() < 2) return one;
  for (int ranks = 2; ranks <= 4; ++ranks) {
    const fs::path& dir = dirs[static_cast<std::size_t>(ranks - 1)];
    const std::string at = name + " on " + std::to_string(ranks) + " ranks";
    EXPECT_EQ(slurp(dir / "history.csv"), history) << at;
    const nlohmann::json s = nlohmann::json::parse(slurp(dir / "summary.json"));
    EXPECT_EQ(s["ranks"], ranks) << at;
    for (const char* key : {"steps", "time", "particles", "frames", "energy", "error", "outflow"})
      EXPECT_EQ(s.value(key, nlohmann::json()), one.value(key, nlohmann::json())) << at << ": " << key;
    const std::vector<std::string> f = frames(dir);
    EXPECT_EQ(f.size(), one_frames.size()) << at;
    if (f.size() != one_frames.size()) continue;
    for (std::size_t k : {std::size_t{1}, f.size() - 1}) {
      EXPECT_TRUE(f[k].ends_with(".pvtp")) << at;
      EXPECT_EQ(pieces(dir, f[k]).size(), static_cast<std::size_t>(ranks)) << at;
      for (const auto& [field, components] : std::vector<std::pair<std::string, int>>{
               {"", 3}, {"velocity", 3}, {"stress", 6}, {"F", 9}, {"volume", 1}, {"mass", 1}, {"id", 1}})
        EXPECT_TRUE(
            same_bits(by_id(dir, f[k], field, components), by_id(dirs[0], one_frames[k], field, components)))
            << at << ", frame " << k << ": " << (field.empty() ? "positions" : field);
    }
  }
  for (const fs::path& dir : dirs) fs::remove_all(dir);
  return one;
}

TEST(DistributedRun, CollidingDisksSameBitsOnOneToFourRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  expect_same_on_one_to_four_ranks("disks", (source_dir / "examples/colliding-disks/scene.toml").string(),
                                   "--set output.every=0.5");
}

TEST(DistributedRun, AxisAlignedSameBitsOnOneToFourRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  expect_same_on_one_to_four_ranks("axis_aligned", (source_dir / "examples/axis-aligned/scene.toml").string(),
                                   "--set simulation.end_time=0.01 --set output.every=0.005");
}

TEST(DistributedRun, RigidPlatenReactionSameBitsOnOneToFourRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  // The upsetting example made explicit and plane strain: the platen's reaction in history.csv, summed over
  // the nodes each rank owns, is the same bits on every division.
  expect_same_on_one_to_four_ranks("platen", (source_dir / "examples/implicit/upsetting.toml").string(),
                                   "--set simulation.integrator=musl --set simulation.geometry=plane-strain "
                                   "--set simulation.end_time=2e-5 --set output.every=1e-5");
}

TEST(DistributedRun, OutflowSameBitsOnOneToFourRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  // A block thrown down under gravity through the outflow face y = 0 (support.hpp, as OutflowRun.*): what has
  // left, counted on whichever rank held each particle, is the same bits on every division.
  const fs::path dir = scratch("distributed", "outflow_scene");
  std::ofstream(dir / "outflow.toml") << mpm::testing::outflow_scene();
  const nlohmann::json one = expect_same_on_one_to_four_ranks("outflow", (dir / "outflow.toml").string(), "");
  EXPECT_EQ(one["outflow"]["particles"].get<int>(),
            112);  // measured: 112 of the 128 particles leave by t = 0.2 s
  fs::remove_all(dir);
}

TEST(DistributedRun, TractionSameBitsOnOneToFourRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  // A bar held at x = 0 and pulled at its free end by a traction: the load acts on the surface particles of
  // whichever rank holds them, and its work in history.csv is summed over the ranks.
  const fs::path dir = scratch("distributed", "traction_scene");
  std::ofstream(dir / "traction.toml") << R"toml([simulation]
end_time = 0.05
cfl = 0.4
integrator = "musl"
kernel = "cpgimp"
[output]
every = 0.025
[grid]
lo = [0.0, 0.0]
hi = [1.0, 0.5]
cells = [20, 10]
faces = { x-min = "fixed" }
[[materials]]
name = "m"
E = 1e5
nu = 0.3
density = 1000
[[bodies]]
name = "bar"
shape = "box"
lo = [0.0, 0.1]
hi = [0.6, 0.35]
[[loads.traction]]
body = "bar"
face = "x-max"
traction = [2000.0, 0.0]
)toml";
  const nlohmann::json one =
      expect_same_on_one_to_four_ranks("traction", (dir / "traction.toml").string(), "");
  EXPECT_GT(one["energy"]["external_work"].get<double>(),
            0.0);  // the traction pulls the bar the way it moves
  fs::remove_all(dir);
}

TEST(DistributedRun, BenchReportsRanksThreadsAndCommunication) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  const fs::path dir = scratch("distributed", "bench");
  const std::string cmd = mpirun(2) + " bench --particles 40000 --steps 3 --repeat 1 --threads 1 --json >" +
                          (dir / "out.json").string() + " 2>" + (dir / "err.txt").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "err.txt");
  const std::string out = slurp(dir / "out.json");
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << "one object, from rank 0: " << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j["ranks"], 2);
  EXPECT_EQ(j["threads"], 1);
  EXPECT_EQ(j["particles"], 40000);  // the whole block: 100 x 100 cells at 2 x 2 per cell
  const double seconds = j["seconds"], talk = j["communication_seconds"];
  EXPECT_GT(talk, 0.0);
  EXPECT_LT(talk, seconds);
  EXPECT_DOUBLE_EQ(j["particle_steps_per_second"].get<double>(), 40000.0 * 3 / seconds);
  fs::remove_all(dir);
}

TEST(DistributedRun, ImplicitSaysItRunsInOneProcess) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  const fs::path dir = scratch("distributed", "refusals");
  const std::string bar = (source_dir / "examples/implicit/elastic-bar.toml").string();
  EXPECT_EQ(run_on(2, bar, "--out " + (dir / "out").string(), dir / "log.txt"), 2);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("the implicit integrator runs in one process"), std::string::npos) << log;
  EXPECT_EQ(mpm_lines(log), 1) << "once, from rank 0: " << log;
  fs::remove_all(dir);
}

}  // namespace

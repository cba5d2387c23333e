// Checkpoints of runs divided between ranks: `mpirun -np N mpm run --stop-after K` writes one checkpoint.h5
// that holds, by particle id, the same bits as one process's checkpoint after K steps; restarted on M ranks
// (M = 1 to 4, M != N) the run ends with the same history.csv, byte for byte, the same summary figures, the
// same last frame and the same final checkpoint (by id, to the bit) as the uninterrupted one-process run.
// Cases: the colliding disks (Neo-Hookean, particles crossing between ranks), the explicit upsetting (von
// Mises state, a rigid platen's displacement), the outflow block (particles leave before the checkpoint) and
// a run that a signal to one of its ranks interrupts. Skipped without MPI.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "distributed_support.hpp"
#include "mpm/io/checkpoint.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

/// The rows of every array of rows of a checkpoint, reordered by particle id; the other entries as they are.
mpm::io::CheckpointData sorted_by_id(mpm::io::CheckpointData c) {
  const std::vector<std::int64_t> id = c.integers.at("id");
  std::vector<std::size_t> order(id.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
  const auto reorder = [&](auto& values, std::int64_t width) {
    auto out = values;
    for (std::size_t k = 0; k < order.size(); ++k)
      std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(order[k]) * width, width,
                  out.begin() + static_cast<std::ptrdiff_t>(k) * width);
    values = out;
  };
  for (const auto& [name, width] : c.row_widths) {
    if (c.reals.count(name)) reorder(c.reals[name], width);
    if (c.integers.count(name)) reorder(c.integers[name], width);
  }
  return c;
}

/// Whether two checkpoints hold the same entries, reals to the bit (the texts but the scene's path-free
/// text).
void expect_same_checkpoints(const mpm::io::CheckpointData& a, const mpm::io::CheckpointData& b,
                             const std::string& at) {
  EXPECT_EQ(a.row_widths, b.row_widths) << at;
  EXPECT_EQ(a.integers, b.integers) << at;
  EXPECT_EQ(a.integer_scalars, b.integer_scalars) << at;
  EXPECT_EQ(a.texts, b.texts) << at;
  ASSERT_EQ(a.reals.size(), b.reals.size()) << at;
  for (const auto& [name, values] : a.reals)
    EXPECT_TRUE(b.reals.count(name) && same_bits(values, b.reals.at(name))) << at << ": " << name;
  ASSERT_EQ(a.real_scalars.size(), b.real_scalars.size()) << at;
  for (const auto& [name, value] : a.real_scalars)
    EXPECT_TRUE(b.real_scalars.count(name) && same_bits({value}, {b.real_scalars.at(name)}))
        << at << ": " << name;
}

/// One process runs the scene through; `writer` ranks stop after `stop_after` steps with a checkpoint, which
/// each of `restarts` ranks continues (a copy each). Every continuation must end as the one-process run did.
void expect_restarts_same(const std::string& name, const std::string& scene, const std::string& args,
                          int stop_after, int writer, const std::vector<int>& restarts) {
  const fs::path dir = scratch("distributed_restart", name);
  const auto run = [&](int ranks, const fs::path& out, const std::string& more) {
    const int status = run_on(ranks, scene, args + " --out " + out.string() + " " + more, dir / "log.txt");
    EXPECT_EQ(status, 0) << name << ", " << ranks << " ranks " << more << ": " << slurp(dir / "log.txt");
    return status == 0;
  };
  // --checkpoint-every past the end: the finished run writes its final state.
  const std::string final_checkpoint = "--checkpoint-every 100000";
  if (!run(1, dir / "one", final_checkpoint) ||
      !run(1, dir / "one_stopped", "--stop-after " + std::to_string(stop_after)) ||
      !run(writer, dir / "stopped", "--stop-after " + std::to_string(stop_after)))
    return;
  // The divided run's one file holds one process's particles, by id, to the bit.
  expect_same_checkpoints(sorted_by_id(mpm::io::read_checkpoint(dir / "stopped/checkpoint.h5")),
                          sorted_by_id(mpm::io::read_checkpoint(dir / "one_stopped/checkpoint.h5")),
                          name + ": checkpoint of " + std::to_string(writer) + " ranks");
  const mpm::io::CheckpointData one_end = sorted_by_id(mpm::io::read_checkpoint(dir / "one/checkpoint.h5"));
  const std::string history = slurp(dir / "one/history.csv");
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir / "one/summary.json"));
  const std::vector<std::string> one_frames = frames(dir / "one");
  for (int ranks : restarts) {
    const std::string at =
        name + ": written on " + std::to_string(writer) + " ranks, restarted on " + std::to_string(ranks);
    const fs::path out = dir / ("restart" + std::to_string(ranks));
    fs::copy(dir / "stopped", out, fs::copy_options::recursive);
    if (!run(ranks, out, "--restart " + (out / "checkpoint.h5").string() + " " + final_checkpoint)) continue;
    EXPECT_EQ(slurp(out / "history.csv"), history) << at;
    const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
    for (const char* key : {"steps", "time", "particles", "frames", "energy", "error", "outflow"})
      EXPECT_EQ(s.value(key, nlohmann::json()), summary.value(key, nlohmann::json())) << at << ": " << key;
    const std::vector<std::string> f = frames(out);
    ASSERT_EQ(f.size(), one_frames.size()) << at;
    for (const auto& [field, components] :
         std::vector<std::pair<std::string, int>>{{"", 3}, {"velocity", 3}, {"stress", 6}, {"id", 1}})
      EXPECT_TRUE(same_bits(by_id(out, f.back(), field, components),
                            by_id(dir / "one", one_frames.back(), field, components)))
          << at << ", last frame: " << (field.empty() ? "positions" : field);
    expect_same_checkpoints(sorted_by_id(mpm::io::read_checkpoint(out / "checkpoint.h5")), one_end,
                            at + ", at the end");
  }
  fs::remove_all(dir);
}

TEST(DistributedRestart, CollidingDisksFromTwoRanksOnOneThreeAndFour) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  if (!mpm::io::collective_checkpoints()) GTEST_SKIP() << "built without parallel HDF5";
  expect_restarts_same("disks", (source_dir / "examples/colliding-disks/scene.toml").string(),
                       "--set output.every=0.5", 40, 2, {1, 3, 4});
}

TEST(DistributedRestart, RigidPlatenAndPlasticStateFromThreeRanksOnOneAndTwo) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  if (!mpm::io::collective_checkpoints()) GTEST_SKIP() << "built without parallel HDF5";
  expect_restarts_same("platen", (source_dir / "examples/implicit/upsetting.toml").string(),
                       "--set simulation.integrator=musl --set simulation.geometry=plane-strain "
                       "--set simulation.end_time=2e-5 --set output.every=1e-5",
                       25, 3, {1, 2});
}

TEST(DistributedRestart, OutflowFromFourRanksOnOneAndTwo) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  if (!mpm::io::collective_checkpoints()) GTEST_SKIP() << "built without parallel HDF5";
  const fs::path dir = scratch("distributed_restart", "outflow_scene");
  std::ofstream(dir / "outflow.toml") << outflow_scene();
  expect_restarts_same("outflow", (dir / "outflow.toml").string(), "", 60, 4, {1, 2});
  fs::remove_all(dir);
}

// A rank emptied by the outflow still writes the collective B_p rows of an APIC run: it once skipped them,
// judging by its own (empty) particles, and the other ranks waited for it forever.
TEST(DistributedRestart, ApicOutflowWithAnEmptiedRankFromFourRanksOnOne) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  if (!mpm::io::collective_checkpoints()) GTEST_SKIP() << "built without parallel HDF5";
  const fs::path dir = scratch("distributed_restart", "apic_outflow_scene");
  std::ofstream(dir / "outflow.toml") << outflow_scene();
  expect_restarts_same("apic_outflow", (dir / "outflow.toml").string(), "--set simulation.transfer=apic", 60,
                       4, {1});
  fs::remove_all(dir);
}

TEST(DistributedRestart, SignalOnOneRankCheckpointsEveryRankAndTheRestartEndsBitwiseEqual) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  if (!mpm::io::collective_checkpoints()) GTEST_SKIP() << "built without parallel HDF5";
  // The 129,600-particle block of the Signals tests on 2 ranks: SIGTERM to one rank stops both after the same
  // step, and they write the checkpoint together; restarted on 3 ranks the run stops as one process's at the
  // same step. The run is ~880 steps long, so that the signal, sent once history.csv shows rows (its buffer
  // is written ~47 steps in), finds it running even on a loaded machine; the two runs compared stop 20 steps
  // after the interrupted one did.
  const fs::path dir = scratch("distributed_restart", "signal");
  const fs::path scene = dir / "block.toml", out = dir / "out";
  std::ofstream(scene) << block_scene("4e-2");
  const std::string rank_command =
      std::string(MPM_BINARY) + " run " + scene.string() + " --quiet --out " + out.string();
  const std::string launch = mpirun(2) + " run " + scene.string() + " --quiet --out " + out.string() + " >" +
                             (dir / "log.txt").string() + " 2>&1";
  const pid_t shell = fork();
  if (shell == 0) {
    execl("/bin/sh", "sh", "-c", launch.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  const auto rows = [&] {
    const std::string h = slurp(out / "history.csv");
    return std::count(h.begin(), h.end(), '\n');
  };
  while (std::chrono::steady_clock::now() < give_up && rows() < 4)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  // One rank, found by its exact command line (mpirun's and the shell's differ).
  const int killed = std::system(("pkill -TERM -o -f -x '" + rank_command + "'").c_str());
  ASSERT_EQ(killed, 0) << "no rank found running " << rank_command;
  int status = 0;
  waitpid(shell, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGTERM)
      << status << ": " << slurp(dir / "log.txt");
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_EQ(s["signal"], "SIGTERM");
  EXPECT_EQ(mpm::io::read_checkpoint(out / "checkpoint.h5").integer_scalars.at("steps"),
            s["steps"].get<std::int64_t>());
  EXPECT_LT(s["time"].get<double>(), 4e-2);
  const std::int64_t interrupted_at = s["steps"].get<std::int64_t>();
  ASSERT_EQ(
      run_on(3, scene.string(),
             " --stop-after 20 --out " + out.string() + " --restart " + (out / "checkpoint.h5").string(),
             dir / "log.txt"),
      0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(
      run_on(1, scene.string(),
             " --stop-after " + std::to_string(interrupted_at + 20) + " --out " + (dir / "one").string(),
             dir / "log.txt"),
      0)
      << slurp(dir / "log.txt");
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "summary.json"))["steps"], interrupted_at + 20);
  EXPECT_EQ(slurp(out / "history.csv"), slurp(dir / "one/history.csv"));
  expect_same_checkpoints(sorted_by_id(mpm::io::read_checkpoint(out / "checkpoint.h5")),
                          sorted_by_id(mpm::io::read_checkpoint(dir / "one/checkpoint.h5")),
                          "interrupted on 2, stopped on 3");
  fs::remove_all(dir);
}

TEST(DistributedRestart, BadCheckpointSaidOnceOnThreeRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  // A file that is no checkpoint, and a checkpoint of another scene: one line from rank 0, exit status 2.
  const fs::path dir = scratch("distributed_restart", "bad");
  std::ofstream(dir / "not.h5") << "not a checkpoint";
  const std::string disks = (source_dir / "examples/colliding-disks/scene.toml").string();
  EXPECT_EQ(run_on(3, disks, "--out " + (dir / "a").string() + " --restart " + (dir / "not.h5").string(),
                   dir / "log.txt"),
            2);
  std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("--restart: checkpoint " + (dir / "not.h5").string() + ": not an HDF5 file"),
            std::string::npos)
      << log;
  EXPECT_EQ(mpm_lines(log), 1) << log;
  ASSERT_EQ(run_on(1, disks, "--out " + (dir / "a").string() + " --stop-after 2", dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  const std::string block = (source_dir / "examples/3d-block/scene.toml").string();
  EXPECT_EQ(
      run_on(3, block, "--out " + (dir / "b").string() + " --restart " + (dir / "a/checkpoint.h5").string(),
             dir / "log.txt"),
      2);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("the checkpoint holds a different scene"), std::string::npos) << log;
  EXPECT_EQ(mpm_lines(log), 1) << log;
  fs::remove_all(dir);
}

}  // namespace

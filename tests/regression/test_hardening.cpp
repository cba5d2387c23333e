// `mpm run` refuses what cannot run and stops cleanly: the budget and --dry-run, limits on absurd input, the
// output folder checked before anything is written, SIGINT and SIGTERM, write failures, and memory exhaustion.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "support.hpp"
#include "mpm/io/checkpoint.hpp"

namespace {
namespace fs = std::filesystem;

const fs::path source_dir = fs::path(__FILE__).parent_path().parent_path().parent_path();
const std::string disks = (source_dir / "examples/colliding-disks/scene.toml").string();

using mpm::testing::slurp;

/// A fresh temporary folder per test.
fs::path scratch(const std::string& name) { return mpm::testing::scratch("mpm_hardening", name); }

struct Outcome {
  int status;
  std::string out, err;
};

/// Run `mpm ARGS` through the shell (`prefix` goes before it, e.g. "ulimit -f 64;").
Outcome mpm(const std::string& args, const fs::path& dir, const std::string& prefix = "") {
  const std::string cmd = "bash -c '" + prefix + " exec " + std::string(MPM_BINARY) + " " + args + "' >" +
                          (dir / "stdout").string() + " 2>" + (dir / "stderr").string();
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir / "stdout"), slurp(dir / "stderr")};
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// The 129,600-particle block of support.hpp, with `extra` appended, written as a scene file.
fs::path block_scene(const fs::path& dir, const std::string& extra = "") {
  std::ofstream(dir / "block.toml") << mpm::testing::block_scene("4e-3") << extra;
  return dir / "block.toml";
}

TEST(Budget, DryRunPrintsTheBudgetWritesNothingAndExits0) {
  const fs::path dir = scratch("dry");
  const Outcome o = mpm("run " + disks + " --out " + (dir / "out").string() + " --dry-run", dir);
  EXPECT_EQ(o.status, 0) << o.err;
  // The two disks seed 208 particles each (examples/colliding-disks/README.md); 23 x 23 nodes with the ghosts.
  EXPECT_EQ(o.out.rfind("budget: 416 particles, 529 nodes, ", 0), 0u) << o.out;
  EXPECT_EQ(lines(o.out), 1);
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(Budget, EstimatedMemoryMatchesThePeakOfTheRun) {
#if MPM_SANITIZED
  GTEST_SKIP() << "a sanitizer's shadow memory is not the engine's";
#endif
  // 129,600 particles: the engine and a frame dominate the fixed 16 MB. Measured: the estimate is within 1% of the
  // peak resident memory (docs/hardening.md); the bound leaves room for allocator and thread-stack variation.
  const fs::path dir = scratch("memory");
  const Outcome o = mpm("run " + block_scene(dir).string() + " --quiet --out " + (dir / "out").string(), dir);
  ASSERT_EQ(o.status, 0) << o.err;
  const nlohmann::json s = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  const double estimated = s["memory"]["estimated_bytes"], peak = s["memory"]["peak_bytes"];
  EXPECT_NEAR(estimated / peak, 1.0, 0.1) << estimated << " " << peak;
  EXPECT_EQ(s["particles"], 129600);
  fs::remove_all(dir);
}

TEST(Budget, AbsurdScenesAreRefusedWithOneLineAndNothingWritten) {
  const fs::path dir = scratch("absurd");
  const std::string out = " --out " + (dir / "out").string();
  const fs::path fixed_step = dir / "fixed-step.toml";  // 4e-3 / 1e-12 = 4e9 steps
  std::string text = slurp(block_scene(dir));
  text.replace(text.find("cfl = 0.5"), 9, "dt = 1e-12");
  std::ofstream(fixed_step) << text;
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      // About 4e9 particles: more than 2^31 - 1, named by the body that seeds most.
      {"run " + disks + out + " --set grid.cells=[40000,40000] --set bodies.0.ppc=4", "bodies[0] (lower-left): seeds about"},
      // end_time = 1e300 with a CFL step: ~6e301 steps.
      {"run " + disks + out + " --set simulation.end_time=1e300 --set output.every=0", "simulation.end_time: about"},
      {"run " + disks + out + " --set simulation.end_time=1e300", "output.every: end_time / every ="},
      {"run " + disks + out + " --max-memory 1M", "more than the 1.05 MB allowed (--max-memory)"},
      {"run " + disks + " --out /proc/mpm-out", "--out /proc/mpm-out: cannot write in /proc"},
      {"run " + disks + " --out " + disks, "exists and is not a folder"},
      {"run " + disks + out + " --set grid.cells=[2000000,4]", "expected at most 1000000 cells per axis"},
      {"run " + disks + out + " --set bodies.0.ppc=17", "expected at least 1 and at most 16 particles per cell"},
      {"run " + fixed_step.string() + out, "simulation.dt: end_time / dt"},
      {"run " + disks + out + " --max-memory lots", "--max-memory: expected a positive size"},
      {"run " + source_dir.string() + out, "cannot open the scene file"},
      {"run " + disks + out + " --threads -3", "--threads: expected a non-negative count"},
      {"run " + disks + out + " --restart " + disks, "--restart"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const Outcome o = mpm(c.args, dir);
    EXPECT_EQ(o.status, 2);
    EXPECT_EQ(lines(o.err), 1) << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << o.err;
    EXPECT_TRUE(o.out.empty()) << o.out;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  fs::remove_all(dir);
}

/// Start `mpm run` in a child process, its standard error into `err`; return its pid.
pid_t start(const std::vector<std::string>& args, const fs::path& err) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>(MPM_BINARY), const_cast<char*>("run")};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int null = ::open("/dev/null", O_WRONLY);
    const int err_file = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(null, 1);
    dup2(err_file, 2);
    execv(MPM_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

/// Wait until the run `pid` has at least `rows` steps in its history. False if it ended before, or had not after a
/// minute (then it is killed): either way it is gone.
bool wait_for_steps(pid_t pid, const fs::path& history, int rows) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (lines(slurp(history)) < rows + 2) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return false;
    if (std::chrono::steady_clock::now() > give_up) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

int wait_status(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

TEST(Signals, InterruptWritesACheckpointAndTheRestartEndsBitwiseEqual) {
  const fs::path dir = scratch("signals");
  const std::string scene = block_scene(dir).string();
  for (int signal : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(signal == SIGINT ? "SIGINT" : "SIGTERM");
    const fs::path out = dir / ("out" + std::to_string(signal));
    const pid_t pid = start({scene, "--quiet", "--out", out.string()}, dir / "stderr");
    ASSERT_TRUE(wait_for_steps(pid, out / "history.csv", 3)) << slurp(dir / "stderr");
    kill(pid, signal);
    EXPECT_EQ(wait_status(pid), 128 + signal) << slurp(dir / "stderr");
    const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
    EXPECT_EQ(s["status"], "interrupted");
    EXPECT_EQ(s["signal"], signal == SIGINT ? "SIGINT" : "SIGTERM");
    const std::int64_t steps = mpm::io::read_checkpoint(out / "checkpoint.h5").integer_scalars.at("steps");
    EXPECT_EQ(steps, s["steps"].get<std::int64_t>());
    EXPECT_LT(s["time"].get<double>(), 4e-3);
    // Continue to the end, and compare with a run that was never interrupted.
    ASSERT_EQ(mpm("run " + scene + " --quiet --checkpoint-every 100000 --out " + out.string() + " --restart " +
                      (out / "checkpoint.h5").string(),
                  dir)
                  .status,
              0);
  }
  ASSERT_EQ(mpm("run " + scene + " --quiet --checkpoint-every 100000 --out " + (dir / "ref").string(), dir).status, 0);
  const mpm::io::CheckpointData ref = mpm::io::read_checkpoint(dir / "ref/checkpoint.h5");
  for (int signal : {SIGINT, SIGTERM}) {
    const mpm::io::CheckpointData c = mpm::io::read_checkpoint(dir / ("out" + std::to_string(signal)) / "checkpoint.h5");
    EXPECT_EQ(c.integer_scalars.at("steps"), ref.integer_scalars.at("steps"));
    EXPECT_TRUE(c.reals == ref.reals);  // bitwise: the doubles compare equal and none is NaN
    EXPECT_EQ(slurp(dir / ("out" + std::to_string(signal)) / "history.csv"), slurp(dir / "ref/history.csv"));
  }
  fs::remove_all(dir);
}

TEST(Signals, ASecondSignalEndsTheProgramAtOnce) {
  const fs::path dir = scratch("second");
  const fs::path out = dir / "out";
  // One checkpoint per step: after the first signal the run still has a step and a checkpoint to finish.
  const pid_t pid =
      start({block_scene(dir).string(), "--quiet", "--checkpoint-every", "1", "--out", out.string()}, dir / "stderr");
  ASSERT_TRUE(wait_for_steps(pid, out / "history.csv", 2)) << slurp(dir / "stderr");
  // Two different signals, since two of the same may merge into one before the run sees them. Either may be handled
  // first (any of the run's threads takes them); the second ends the program with 128 + its number.
  kill(pid, SIGINT);
  kill(pid, SIGTERM);
  const int status = wait_status(pid);
  EXPECT_TRUE(status == 128 + SIGINT || status == 128 + SIGTERM) << status << slurp(dir / "stderr");
  EXPECT_FALSE(fs::exists(out / "summary.json"));  // ended without writing its summary
  fs::remove_all(dir);
}

TEST(WriteFailures, FileSizeLimitExits1NamingTheFileAndTheCheckpointStaysReadable) {
  // ulimit -f 200: no file may grow past 200 kB. The history (one ~150-byte row per step of the colliding disks at
  // a 50 times smaller step) passes it after ~1,400 rows; the first frame is 101 kB, a checkpoint (every 50 steps)
  // 71 kB.
  const fs::path dir = scratch("fsize");
  const Outcome o = mpm("run " + disks + " --quiet --checkpoint-every 50 --set simulation.cfl=0.01 --set output.every=0 --out " +
                            (dir / "out").string(),
                        dir, "ulimit -f 200;");
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(lines(o.err), 1) << o.err;
  EXPECT_NE(o.err.find("cannot write " + (dir / "out/history.csv").string()), std::string::npos) << o.err;
  const mpm::io::CheckpointData c = mpm::io::read_checkpoint(dir / "out/checkpoint.h5");
  EXPECT_EQ(c.integer_scalars.at("steps") % 50, 0);
  EXPECT_GT(c.integer_scalars.at("steps"), 0);
  const nlohmann::json s = nlohmann::json::parse(slurp(dir / "out/summary.json"));
  EXPECT_EQ(s["status"], "failed");
  fs::remove_all(dir);
}

TEST(WriteFailures, OutputFolderRemovedDuringTheRunExits1NamingAFile) {
  const fs::path dir = scratch("removed");
  const fs::path out = dir / "out";
  const pid_t pid =
      start({block_scene(dir, "[output]\nevery = 1e-4\n").string(), "--quiet", "--out", out.string()}, dir / "stderr");
  ASSERT_TRUE(wait_for_steps(pid, out / "history.csv", 2)) << slurp(dir / "stderr");
  std::error_code ec;
  for (int tries = 0; tries < 1000 && fs::exists(out); ++tries) fs::remove_all(out, ec);  // the run writes on
  const int status = wait_status(pid);
  const std::string err = slurp(dir / "stderr");
  EXPECT_EQ(status, 1) << err;
  EXPECT_NE(err.find("cannot write " + out.string() + "/"), std::string::npos) << err;
  fs::remove_all(dir);
}

TEST(Memory, AnAllocationThatFailsEndsWithExit1AndOneLine) {
#if MPM_SANITIZED
  GTEST_SKIP() << "a sanitizer reserves more address space than the limit";
#endif
  // ulimit -v 600000 (600 MB of address space) against a scene the budget puts at ~1 GB: --max-memory lets it pass
  // the budget, and the allocation fails while the particles are seeded.
  const fs::path dir = scratch("oom");
  const Outcome o = mpm("run " + block_scene(dir).string() + " --set grid.cells=[900,900] --max-memory 100G --out " +
                            (dir / "out").string(),
                        dir, "ulimit -v 600000;");
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(lines(o.err), 1) << o.err;
  EXPECT_NE(o.err.find("out of memory"), std::string::npos) << o.err;
  fs::remove_all(dir);
}

}  // namespace

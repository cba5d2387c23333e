// An explicit run with a rate-form material, a rigid body and axisymmetry (the upsetting, integrator = "cd")
// stopped and restarted from its checkpoint ends bitwise equal to one uninterrupted run: the checkpoint carries
// the material state, the volumes and the rigid body's displacement.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support.hpp"

namespace {
namespace fs = std::filesystem;
using mpm::testing::scratch;
using mpm::testing::slurp;

int run(const std::string& args, const fs::path& log) {
  const fs::path root = fs::path(__FILE__).parent_path().parent_path().parent_path();
  const std::string command = std::string(MPM_BINARY) + " run " + (root / "examples/implicit/upsetting.toml").string() +
                              " --quiet --set simulation.integrator=cd --set simulation.end_time=5e-5 " + args +
                              " > " + log.string() + " 2>&1";
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

TEST(RateFormRestart, IsBitwise) {
  const fs::path dir = scratch("rate_form", "restart");
  const std::string one = (dir / "one").string(), two = (dir / "two").string();
  ASSERT_EQ(run("--out " + one, dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(run("--out " + two + " --stop-after 300", dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(run("--out " + two + " --restart " + two + "/checkpoint.h5", dir / "log"), 0) << slurp(dir / "log");
  const std::string history = slurp(fs::path(one) / "history.csv");
  EXPECT_GT(history.size(), 1000u);
  EXPECT_EQ(history, slurp(fs::path(two) / "history.csv"));
  for (const auto& f : fs::directory_iterator(one)) {
    if (f.path().extension() != ".vtp") continue;
    EXPECT_EQ(slurp(f.path()), slurp(fs::path(two) / f.path().filename())) << f.path();
  }
  fs::remove_all(dir);
}

}  // namespace

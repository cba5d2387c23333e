// An explicit run with a rate-form material, a rigid body and axisymmetry (the upsetting, integrator = "cd")
// stopped and restarted from its checkpoint ends bitwise equal to one uninterrupted run: the checkpoint
// carries the material state, the volumes and the rigid body's displacement. So do an APIC run and a CPDI2
// run, in both engines.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support.hpp"

namespace {
namespace fs = std::filesystem;
using mpm::testing::scratch;
using mpm::testing::slurp;

int run(const std::string& scene, const std::string& args, const fs::path& log) {
  const fs::path root = fs::path(__FILE__).parent_path().parent_path().parent_path();
  const std::string command = std::string(MPM_BINARY) + " run " + (root / scene).string() + " --quiet " +
                              args + " > " + log.string() + " 2>&1";
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

/// Run `scene` with `sets` once to the end and once stopped after `stop` steps and restarted; the histories
/// and every frame must be the same bytes.
void expect_bitwise_restart(const std::string& name, const std::string& scene, const std::string& sets,
                            int stop) {
  const fs::path dir = scratch(name, "restart");
  const std::string one = (dir / "one").string(), two = (dir / "two").string();
  ASSERT_EQ(run(scene, sets + " --out " + one, dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(run(scene, sets + " --out " + two + " --stop-after " + std::to_string(stop), dir / "log"), 0)
      << slurp(dir / "log");
  ASSERT_EQ(run(scene, sets + " --out " + two + " --restart " + two + "/checkpoint.h5", dir / "log"), 0)
      << slurp(dir / "log");
  const std::string history = slurp(fs::path(one) / "history.csv");
  EXPECT_GT(history.size(), 1000u);
  EXPECT_EQ(history, slurp(fs::path(two) / "history.csv"));
  for (const auto& f : fs::directory_iterator(one)) {
    if (f.path().extension() != ".vtp") continue;
    EXPECT_EQ(slurp(f.path()), slurp(fs::path(two) / f.path().filename())) << f.path();
  }
  fs::remove_all(dir);
}

TEST(RateFormRestart, IsBitwise) {
  expect_bitwise_restart("rate_form", "examples/implicit/upsetting.toml",
                         "--set simulation.integrator=cd --set simulation.end_time=5e-5", 300);
}

// APIC's affine matrices B_p travel in the checkpoint, in both engines (the colliding disks, quadratic
// B-splines).
TEST(ApicRestart, IsBitwiseInBothEngines) {
  const std::string apic =
      "--set simulation.transfer=apic --set simulation.kernel=bspline2 --set simulation.end_time=1";
  expect_bitwise_restart("apic_explicit", "examples/colliding-disks/scene.toml", apic, 30);
  expect_bitwise_restart("apic_implicit", "examples/colliding-disks/scene.toml",
                         apic + " --set simulation.integrator=implicit", 10);
}

// CPDI2's corners travel in the checkpoint, in both engines (the colliding disks).
TEST(Cpdi2Restart, IsBitwiseInBothEngines) {
  const std::string cpdi2 = "--set simulation.kernel=cpdi2 --set simulation.end_time=1";
  expect_bitwise_restart("cpdi2_explicit", "examples/colliding-disks/scene.toml", cpdi2, 30);
  expect_bitwise_restart("cpdi2_implicit", "examples/colliding-disks/scene.toml",
                         cpdi2 + " --set simulation.integrator=implicit", 10);
}

}  // namespace

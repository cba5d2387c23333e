// `mpm run` with the implicit integrator: impossible settings are input errors naming the key, a Newton
// failure that step halving cannot rescue stops with exit status 1 and a checkpoint of the last good state,
// restarts are bitwise, and the frozen-Jacobian preconditioner shortens the Krylov solves without changing
// the answer.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {
namespace fs = std::filesystem;

const fs::path source_dir = fs::path(__FILE__).parent_path().parent_path().parent_path();
const std::string bar = (source_dir / "examples/implicit/elastic-bar.toml").string();
const std::string plastic_bar = (source_dir / "examples/implicit/plastic-bar.toml").string();

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("mpm_implicit_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& f) {
  std::ifstream is(f, std::ios::binary);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

int run(const std::string& args, const fs::path& log) {
  const std::string cmd = std::string(MPM_BINARY) + " run " + args + " >" + log.string() + " 2>&1";
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

nlohmann::json summary(const fs::path& dir) {
  return nlohmann::json::parse(slurp(dir / "summary.json"));
}

struct BadSetting {
  const char* name;
  const char* set;       // --set arguments
  const char* key;       // named in the one-line message
  const char* expected;  // what it says was expected
};

class ImplicitInput : public ::testing::TestWithParam<BadSetting> {};

TEST_P(ImplicitInput, IsAnInputErrorNamingTheKey) {
  const BadSetting& b = GetParam();
  const fs::path dir = scratch("bad");
  const int status = run(bar + " --quiet --out " + (dir / "out").string() + " " + b.set, dir / "log");
  const std::string log = slurp(dir / "log");
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find(b.key), std::string::npos) << log;
  EXPECT_NE(log.find(b.expected), std::string::npos) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
  EXPECT_FALSE(fs::exists(dir / "out")) << "no output for bad input";
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, ImplicitInput,
    ::testing::Values(
        BadSetting{"ThetaAboveOne", "--set implicit.theta=1.5", "implicit.theta",
                   "expected a number in [0, 1]"},
        BadSetting{"ThetaBelowZero", "--set implicit.theta=-0.1", "implicit.theta",
                   "expected a number in [0, 1]"},
        BadSetting{"ZeroNewtonTolerance", "--set implicit.newton_tolerance=0", "implicit.newton_tolerance",
                   "expected a finite number > 0"},
        BadSetting{"NegativeLinearTolerance", "--set implicit.linear_tolerance=-1",
                   "implicit.linear_tolerance", "expected"},
        BadSetting{"ZeroDerivativeStep", "--set implicit.derivative_step=0", "implicit.derivative_step",
                   "expected a finite number > 0"},
        BadSetting{"RestartBelowOne", "--set implicit.restart=0", "implicit.restart",
                   "expected an integer >= 1"},
        BadSetting{"NegativeRefreshAfter", "--set implicit.refresh_after=-1", "implicit.refresh_after",
                   "expected an integer >= 0"},
        BadSetting{"ExplicitAboveCfl", "--set implicit.theta=0 --set implicit.step_factor=10",
                   "implicit.step_factor", "theta = 0 is explicit"},
        BadSetting{"RigidBodyOutsideTheGrid", "--set rigid_bodies.0.lo=[-0.1,0.1]", "rigid_bodies[0].lo",
                   "the rigid body must lie inside the grid"},
        BadSetting{"SofteningToZero",
                   "--set materials.0.model=von-mises --set materials.0.yield_strength=6 "
                   "--set materials.0.limit_strength=8 --set materials.0.hardening=100 --set "
                   "materials.0.softening=50",
                   "materials[0].softening", "the strength H reaches zero"},
        BadSetting{"UnknownSolver", "--set implicit.solver=bicgstab", "implicit.solver",
                   "expected one of newton-gmres, newton-cg, cg"},
        BadSetting{"PeriodicRadialAxis",
                   "--set simulation.geometry=axisymmetric --set "
                   "'grid.faces={x-min=\"periodic\",x-max=\"periodic\"}'",
                   "x-min", "the radial axis of an axisymmetric grid cannot be periodic"},
        BadSetting{"OutflowOnTheAxis",
                   "--set simulation.geometry=axisymmetric --set 'grid.faces={x-min=\"outflow\"}'", "x-min",
                   "the axis r = 0 of an axisymmetric grid cannot be an outflow face"},
        BadSetting{"ConsistentMassWithMomentum", "--set implicit.mass=consistent", "implicit.mass",
                   "the consistent mass matrix needs the velocity formulation"},
        BadSetting{"ConsistentMassWithFrozenJacobian",
                   "--set implicit.mass=consistent --set implicit.formulation=velocity "
                   "--set implicit.preconditioner=frozen-jacobian",
                   "implicit.mass", "use the lumped mass"},
        BadSetting{"ProjectedPositionsWithVelocity",
                   "--set implicit.positions=projected-velocity --set implicit.formulation=velocity",
                   "implicit.positions", "belongs to the momentum formulation"},
        BadSetting{"NewtonLogOfALinearSolve",
                   "--set output.newton_log=on --set implicit.solver=cg --set implicit.formulation=velocity",
                   "output.newton_log", "takes no Newton iterations to log"},
        BadSetting{"NewtonLogOfAnExplicitStep",
                   "--set output.newton_log=on --set implicit.theta=0 --set implicit.step_factor=1 "
                   "--set implicit.start_factor=1",
                   "output.newton_log", "takes no Newton iterations to log"},
        BadSetting{"UnknownPositions", "--set implicit.positions=flip", "implicit.positions",
                   "expected one of momentum, projected-velocity"},
        BadSetting{"NewtonLogOfAnExplicitRun", "--set output.newton_log=on --set simulation.integrator=usl",
                   "output.newton_log", "this run is explicit"},
        BadSetting{"UnknownResidual", "--set implicit.residual=relative", "implicit.residual",
                   "expected one of scaled, unscaled"},
        BadSetting{"CgWithMomentum", "--set implicit.solver=newton-cg", "implicit.solver",
                   "CG needs the symmetric velocity formulation"},
        BadSetting{"NeoHookeanNeedsPlaneStrain",
                   "--set simulation.integrator=usl --set materials.0.model=neo-hookean",
                   "materials[0].model", "a Neo-Hookean material runs in plane strain"}),
    [](const auto& test) { return std::string(test.param.name); });

// One Newton iteration allowed, no halving: the first step fails. The run stops with exit status 1, the
// summary says why, and a checkpoint of the last good state (t = 0) lets a run with workable settings
// continue.
TEST(ImplicitFailure, StopsWithStatusOneAndACheckpointToRestartFrom) {
  const fs::path dir = scratch("failure");
  const std::string out = (dir / "out").string();
  const int status = run(plastic_bar + " --quiet --out " + out +
                             " --set implicit.max_newton=1 --set implicit.max_retries=0 "
                             "--set implicit.newton_tolerance=1e-14",
                         dir / "log");
  const std::string log = slurp(dir / "log");
  EXPECT_EQ(status, 1) << log;
  EXPECT_NE(log.find("the implicit solve failed"), std::string::npos) << log;
  const nlohmann::json s = summary(out);
  EXPECT_EQ(s["status"], "failed");
  EXPECT_NE(s["failure"].get<std::string>().find("after 0 halvings"), std::string::npos);
  ASSERT_TRUE(fs::exists(fs::path(out) / "checkpoint.h5"));
  EXPECT_EQ(run(plastic_bar + " --quiet --out " + out + " --restart " + out + "/checkpoint.h5", dir / "log2"),
            0)
      << slurp(dir / "log2");
  EXPECT_EQ(summary(out)["status"], "ok");
  fs::remove_all(dir);
}

// Stopping after 20 steps and restarting gives the same bytes as one run (history and summary counters).
TEST(ImplicitRestart, IsBitwise) {
  const fs::path dir = scratch("restart");
  const std::string one = (dir / "one").string(), two = (dir / "two").string();
  ASSERT_EQ(run(plastic_bar + " --quiet --out " + one, dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(run(plastic_bar + " --quiet --out " + two + " --stop-after 20", dir / "log"), 0)
      << slurp(dir / "log");
  ASSERT_EQ(run(plastic_bar + " --quiet --out " + two + " --restart " + two + "/checkpoint.h5", dir / "log"),
            0)
      << slurp(dir / "log");
  EXPECT_EQ(slurp(fs::path(one) / "history.csv"), slurp(fs::path(two) / "history.csv"));
  EXPECT_EQ(slurp(fs::path(one) / "particles_0012.vtp"), slurp(fs::path(two) / "particles_0012.vtp"));
  EXPECT_EQ(summary(one)["implicit"], summary(two)["implicit"]);
  fs::remove_all(dir);
}

// The frozen Jacobian (assembled from the particles, sparse LU) on the elastic-plastic bar at 100x: fewer
// Krylov iterations and fewer residual evaluations in all. Measured: 532 GMRES iterations and 686 evaluations
// plain, 85 and 239 preconditioned (77 builds); the bounds below leave a margin of about 1.5x on each.
TEST(FrozenJacobian, ShortensTheKrylovSolves) {
  const fs::path dir = scratch("frozen");
  const std::string plain = (dir / "plain").string(), pre = (dir / "pre").string();
  ASSERT_EQ(run(plastic_bar + " --quiet --out " + plain, dir / "log"), 0) << slurp(dir / "log");
  ASSERT_EQ(run(plastic_bar + " --quiet --out " + pre + " --set implicit.preconditioner=frozen-jacobian",
                dir / "log"),
            0)
      << slurp(dir / "log");
  const nlohmann::json a = summary(plain)["implicit"], b = summary(pre)["implicit"];
  std::printf("krylov: plain %lld, frozen Jacobian %lld (%lld builds); residual evaluations %lld vs %lld\n",
              a["krylov_iterations"].get<long long>(), b["krylov_iterations"].get<long long>(),
              b["preconditioner_builds"].get<long long>(), a["residual_evaluations"].get<long long>(),
              b["residual_evaluations"].get<long long>());
  EXPECT_LT(b["krylov_iterations"].get<long long>(), a["krylov_iterations"].get<long long>() / 4);
  EXPECT_LT(b["residual_evaluations"].get<long long>(), a["residual_evaluations"].get<long long>() / 2);
  EXPECT_GE(b["preconditioner_builds"].get<long long>(), 1);
  fs::remove_all(dir);
}

// On the elastic bar the assembled tangent is the Jacobian itself (to the finite-difference accuracy of the
// material tangent and of Eq. 2.4.18, ~1e-4 relative, and for the Jaumann spin, ~sigma/E = 1e-5), so the
// preconditioned operator is the identity to within linear_tolerance = 1e-3 and every GMRES solve takes one
// iteration. Measured: 44 iterations for 41 Newton steps (momentum), 44 for 44 (velocity), 44 for 41 (plane
// strain); the test allows 25% more than one per Newton step.
TEST(FrozenJacobian, IsTheExactJacobianForLinearElasticity) {
  const fs::path dir = scratch("exact");
  for (const char* variant :
       {"", " --set implicit.formulation=velocity", " --set simulation.geometry=plane-strain"}) {
    const std::string out = (dir / "run").string();
    ASSERT_EQ(run(bar + " --quiet --out " + out + " --set implicit.preconditioner=frozen-jacobian" + variant,
                  dir / "log"),
              0)
        << slurp(dir / "log");
    const nlohmann::json c = summary(out)["implicit"];
    const auto newton = c["newton_iterations"].get<long long>(),
               krylov = c["krylov_iterations"].get<long long>();
    SCOPED_TRACE(variant);
    EXPECT_GE(krylov, newton);
    EXPECT_LE(krylov, newton + newton / 4);
  }
  fs::remove_all(dir);
}

// The same bar in 3-D (all six strain components in the material tangent). Measured: 24 GMRES iterations for
// 24 Newton steps with the preconditioner, 178 without.
TEST(FrozenJacobian, IsTheExactJacobianForLinearElasticityIn3D) {
  const fs::path dir = scratch("exact3d");
  const fs::path scene = dir / "bar3d.toml";
  std::ofstream(scene) << R"([simulation]
dimension = 3
end_time = 10.0
integrator = "implicit"
kernel = "linear"
cfl = 0.5
[implicit]
newton_tolerance = 1e-5
linear_tolerance = 1e-3
step_factor = 100
start_factor = 100
preconditioner = "frozen-jacobian"
[grid]
lo = [0.0, 0.0, 0.0]
hi = [0.7, 0.5, 0.5]
cells = [7, 5, 5]
faces = { x-max = "symmetry" }
[[materials]]
name = "bar"
model = "hypoelastic"
E = 1000.0
nu = 0.3
density = 10.0
[[bodies]]
name = "bar"
shape = "box"
lo = [0.4, 0.1, 0.1]
hi = [0.7, 0.4, 0.4]
ppc = 2
[[rigid_bodies]]
name = "puller"
lo = [0.3, 0.1, 0.1]
hi = [0.4, 0.4, 0.4]
ppc = 2
velocity = [-0.001, 0.0, 0.0]
contact_axes = ["x"]
)";
  const std::string out = (dir / "run").string();
  ASSERT_EQ(run(scene.string() + " --quiet --out " + out, dir / "log"), 0) << slurp(dir / "log");
  const nlohmann::json c = summary(out)["implicit"];
  const auto newton = c["newton_iterations"].get<long long>(),
             krylov = c["krylov_iterations"].get<long long>();
  EXPECT_GE(newton, 20);
  EXPECT_GE(krylov, newton);
  EXPECT_LE(krylov, newton + newton / 4);
  fs::remove_all(dir);
}

}  // namespace

namespace {
// history.csv's last two columns count the Newton and Krylov iterations since t = 0, row by row: they start
// at 0, never fall, and end at summary.json's counts.
TEST(ImplicitHistory, CountsNewtonAndKrylovIterations) {
  const fs::path dir = scratch("history_counts");
  const std::string out = (dir / "out").string();
  ASSERT_EQ(run(bar + " --quiet --out " + out, dir / "log"), 0) << slurp(dir / "log");
  std::istringstream history(slurp(fs::path(out) / "history.csv"));
  std::string line;
  std::getline(history, line);
  EXPECT_NE(line.find(",newton_iterations,krylov_iterations"), std::string::npos) << line;
  long long newton = -1, krylov = -1, rows = 0;
  while (std::getline(history, line)) {
    const std::size_t last = line.rfind(','), before = line.rfind(',', last - 1);
    const long long n = std::stoll(line.substr(before + 1, last - before - 1)),
                    k = std::stoll(line.substr(last + 1));
    if (rows++ == 0) {
      EXPECT_TRUE(n == 0 && k == 0);
    }
    EXPECT_GE(n, newton);
    EXPECT_GE(k, krylov);
    newton = n, krylov = k;
  }
  const nlohmann::json s = summary(out);
  EXPECT_EQ(rows, s["steps"].get<long long>() + 1);
  EXPECT_EQ(newton, s["implicit"]["newton_iterations"].get<long long>());
  EXPECT_EQ(krylov, s["implicit"]["krylov_iterations"].get<long long>());
  fs::remove_all(dir);
}
}  // namespace

// The `mpm` program: bad arguments give one clear line on stderr and exit status 2, with nothing written.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "mpm/core/build_info.hpp"

namespace {

struct Outcome {
  int status;
  std::string out, err;
};

std::string slurp(const std::filesystem::path& f) {
  std::ifstream is(f);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

/// `mpm ARGS`, with the environment assignments `env` (e.g. "NAME=value ") before it.
Outcome run_mpm(const std::string& args, const std::string& env = "") {
  const auto dir = std::filesystem::temp_directory_path() / ("mpm_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cmd = env + std::string(MPM_BINARY) + " " + args + " >" + (dir / "out").string() + " 2>" +
                          (dir / "err").string();
  const int raw = std::system(cmd.c_str());
  Outcome o{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir / "out"), slurp(dir / "err")};
  std::filesystem::remove_all(dir);
  return o;
}

struct BadArgument {
  const char* args;
  const char* message;           ///< a fragment the one-line error must contain
  const char* output = "--out";  ///< the option naming the output that must not be created
};

class CliBadInput : public ::testing::TestWithParam<BadArgument> {};

TEST_P(CliBadInput, ExitsWithStatus2AndOneClearLine) {
  const BadArgument& bad = GetParam();
  const auto out_dir = std::filesystem::temp_directory_path() / "mpm_cli_should_not_exist";
  std::filesystem::remove_all(out_dir);
  const Outcome o = run_mpm(std::string(bad.args) + " " + bad.output + " " + out_dir.string());
  EXPECT_EQ(o.status, 2) << bad.args << "\nstderr: " << o.err;
  EXPECT_NE(o.err.find(bad.message), std::string::npos) << "stderr: " << o.err;
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "stderr: " << o.err;
  EXPECT_TRUE(o.out.empty()) << o.out;
  EXPECT_FALSE(std::filesystem::exists(out_dir)) << "bad input must not create output";
}

INSTANTIATE_TEST_SUITE_P(
    Verify, CliBadInput,
    ::testing::Values(
        BadArgument{"verify axis-aligned --kernel quadratic", "--kernel: unknown name 'quadratic'"},
        BadArgument{"verify axis-aligned --integrator rk4", "--integrator: unknown name 'rk4'"},
        BadArgument{"verify axis-aligned --cells 1", "--cells: expected at least 2"},
        BadArgument{"verify axis-aligned --cells -4", "--cells: expected at least 2"},
        BadArgument{"verify axis-aligned --ppc 0", "--ppc: expected at least 1"},
        BadArgument{"verify axis-aligned --cfl 0", "--cfl: expected a number in (0, 1]"},
        BadArgument{"verify axis-aligned --cfl 1.5", "--cfl: expected a number in (0, 1]"},
        BadArgument{"verify axis-aligned --cfl 2.5 --cfl-speed reference",
                    "--cfl: expected a number in (0, 2] with --cfl-speed reference"},
        BadArgument{"verify axis-aligned --cfl-speed fastest",
                    "--cfl-speed: expected particles or reference"},
        BadArgument{"verify axis-aligned --error energy", "--error: expected particles or nodal"},
        BadArgument{"verify axis-aligned --error nodal --integrator implicit",
                    "--error nodal: the nodal acceleration"},
        BadArgument{"verify axis-aligned --start exact", "--start exact: needs a fixed time step"},
        BadArgument{"verify axis-aligned --start exact --cfl-speed reference --integrator usl",
                    "--start exact: only centered difference (cd) and UVF-MPM (musl)"},
        BadArgument{"verify axis-aligned --cells many", "--cells"},
        BadArgument{"verify axis-aligned --constrained-acceleration sticky",
                    "--constrained-acceleration: expected zero or velocity-difference, got 'sticky'"},
        BadArgument{
            "verify axis-aligned --integrator implicit --constrained-acceleration velocity-difference",
            "--constrained-acceleration: the implicit integrator solves for the end-of-step velocities"},
        BadArgument{
            "verify ring",
            "case: unknown case 'ring' (expected axis-aligned, bar-1d, expanding-ring or shear-wave)"},
        BadArgument{"verify axis-aligned --amplitude 0.5", "--amplitude"},
        BadArgument{"verify bar-1d --amplitude 0.2", "--amplitude: expected A < 0.159"},
        BadArgument{"verify axis-aligned --nu 0.5", "--nu: expected a Poisson's ratio in [0, 0.5)"},
        BadArgument{"verify axis-aligned --nu -0.1", "--nu: expected a Poisson's ratio in [0, 0.5)"},
        BadArgument{"verify expanding-ring --nu 0.2",
                    "--nu: the expanding-ring solution is written for nu = 0"}));

INSTANTIATE_TEST_SUITE_P(
    Converge, CliBadInput,
    ::testing::Values(
        BadArgument{"converge bar-1d --vary dt --values 8,16", "--vary: expected cells or cfl", "--csv"},
        BadArgument{"converge bar-1d --vary cells --values 8,x", "--values: 'x' is not a number", "--csv"},
        BadArgument{"converge bar-1d --vary cells --values 8", "--values: expected at least two", "--csv"},
        BadArgument{"converge bar-1d --vary cells --values 8,1", "--cells: expected at least 2", "--csv"},
        BadArgument{"converge bar-1d --vary cfl --values 0.5,1.5", "--cfl: expected a number in (0, 1]",
                    "--csv"},
        BadArgument{"converge bar-1d --vary cells --values 8,16 --series cpgimp",
                    "--series: expected kernel:integrator pairs such as cpgimp:cd, got 'cpgimp'", "--plot"},
        BadArgument{"converge bar-1d --vary cells --values 8,16 --series cpgimp:cd,linear:rk4",
                    "--series: unknown name 'rk4'", "--plot"}));

TEST(Cli, VersionNamesTheBuildAndNoCommandGivesTheUsage) {
  const Outcome v = run_mpm("--version");
  EXPECT_EQ(v.status, 0) << v.err;
  const mpm::BuildInfo& b = mpm::build_info();
  EXPECT_EQ(v.out, mpm::build_info_text());
  EXPECT_EQ(v.out.rfind("mpm " + b.version + " (commit " + b.commit + ")\n", 0), 0u) << v.out;
  EXPECT_TRUE(b.commit == "unknown" || b.commit.size() == 12 || b.commit.size() == 12 + 8) << b.commit;
  for (const char* line :
       {"\nbuild type: ", "\ncompiler: ", "\nflags: ", "\ninstruction set: ", "\nMPI: ", "\nHDF5: "})
    EXPECT_NE(v.out.find(line), std::string::npos) << line << " in " << v.out;
  const Outcome bare = run_mpm("");
  EXPECT_EQ(bare.status, 2);
  EXPECT_NE(bare.err.find("Subcommands:"), std::string::npos) << bare.err;  // the usage, not one line
  EXPECT_NE(bare.err.find("run"), std::string::npos) << bare.err;
  EXPECT_TRUE(bare.out.empty()) << bare.out;
}

TEST(Cli, ConvergeReportsObservedOrders) {
  const Outcome o = run_mpm("converge bar-1d --amplitude 0.01 --vary cells --values 8,16,32 --json");
  ASSERT_EQ(o.status, 0) << o.err;
  // Same runs as the verification test of the bar (cpGIMP, CD): orders 1.91 and 1.76.
  for (const char* key : {"\"order\":1.9", "\"order\":1.7", "\"cells\":32", "\"status\":\"ok\""})
    EXPECT_NE(o.out.find(key), std::string::npos) << key << " missing in " << o.out;
}

std::uint32_t big_endian(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

TEST(Cli, ConvergePlotsAndTablesEverySeries) {
  const auto dir = std::filesystem::temp_directory_path() / ("mpm_plot_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const Outcome o = run_mpm(
      "converge bar-1d --amplitude 0.01 --vary cells --values 8,16 --series "
      "cpgimp:cd,linear:usl:apic --csv " +
      (dir / "t.csv").string() + " --plot " + (dir / "p.png").string());
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string csv = slurp(dir / "t.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv;  // header + 2 series x 2 points
  EXPECT_NE(csv.find("\ncpgimp,cd,flip,16,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nlinear,usl,apic,16,"), std::string::npos) << csv;  // a series' own transfer
  // A PNG of 5.5 x 4 inches at 120 dpi: the signature, then the IHDR chunk with width and height.
  const std::string png = slurp(dir / "p.png");
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n"));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(big_endian(png, 16), 660u);
  EXPECT_EQ(big_endian(png, 20), 480u);
  EXPECT_FALSE(std::filesystem::exists(dir / "p.plot.json")) << "the plot data file is temporary";
  std::filesystem::remove_all(dir);
}

TEST(Cli, DensityProjectionReportsItsSupport) {
  Outcome o = run_mpm("density-1d --kernel bspline2");
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_NE(o.out.find("nonzero on [-0.25, 1.25]"), std::string::npos) << o.out;
  o = run_mpm("density-1d --cells 7");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--cells: expected a positive multiple of 5"), std::string::npos) << o.err;
  o = run_mpm("density-1d --gimp-length 0.05");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--gimp-length: applies to --kernel ugimp only"), std::string::npos) << o.err;
  o = run_mpm("density-1d --kernel ugimp --gimp-length 0.5");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--gimp-length: expected a smoothing length in (0, h]"), std::string::npos) << o.err;
}

// Started by an MPI launcher among several processes, mpm (one process) refuses with exit 2, said once by
// rank 0, instead of letting every copy write the same output; one process under a launcher runs.
TEST(Cli, StartedAmongSeveralMpiProcessesRefusesOnce) {
  for (const char* launcher : {"OMPI_COMM_WORLD_SIZE=3 OMPI_COMM_WORLD_RANK=", "PMI_SIZE=3 PMI_RANK="}) {
    const Outcome first = run_mpm("verify axis-aligned --cells 4", std::string(launcher) + "0 ");
    EXPECT_EQ(first.status, 2);
    EXPECT_NE(first.err.find("started as one of 3 processes"), std::string::npos) << first.err;
    EXPECT_EQ(first.err.find('\n'), first.err.size() - 1) << "one line: " << first.err;
    EXPECT_TRUE(first.out.empty());
    const Outcome second = run_mpm("verify axis-aligned --cells 4", std::string(launcher) + "2 ");
    EXPECT_EQ(second.status, 2);
    EXPECT_TRUE(second.err.empty() && second.out.empty()) << second.err;
  }
  const Outcome alone =
      run_mpm("verify axis-aligned --cells 4", "OMPI_COMM_WORLD_SIZE=1 OMPI_COMM_WORLD_RANK=0 ");
  EXPECT_EQ(alone.status, 0) << alone.err;
  EXPECT_NE(alone.out.find("axis-aligned"), std::string::npos);
}

TEST(Cli, BenchRejectsBadKernelAndDimension) {
  Outcome o = run_mpm("bench --kernel cubic --steps 1");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(
      o.err.find("--kernel: unknown name 'cubic' (expected one of linear, ugimp, cpgimp, bspline2, bspline3, "
                 "bspline2-clamped, bspline3-clamped, cpdi, ugimp-wide, cpgimp-wide, cpdi2)"),
      std::string::npos)
      << o.err;
  o = run_mpm("bench --dim 4 --steps 1");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--dim"), std::string::npos) << o.err;
}

TEST(Cli, BenchPrintsTheRequiredJsonFields) {
  const Outcome o = run_mpm("bench --particles 400 --steps 3 --repeat 1 --json");
  ASSERT_EQ(o.status, 0) << o.err;
  for (const char* key : {"\"particles\":400", "\"steps\":3", "\"ranks\":1", "\"communication_seconds\":0.0",
                          "\"seconds\":", "\"particle_steps_per_second\":", "\"bytes_per_particle\":"})
    EXPECT_NE(o.out.find(key), std::string::npos) << key << " missing in " << o.out;
}

}  // namespace

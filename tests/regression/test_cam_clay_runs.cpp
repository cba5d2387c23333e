// Modified Cam-Clay in whole runs (examples/geomechanics/oedometer.toml): a clay column in geostatic stress
// pressed one-dimensionally by a rigid platen, in the explicit and the implicit engine. Whatever the stress
// path, each particle's state obeys the exactly integrated volumetric laws
// (docs/geomechanics.md#modified-cam-clay):
//   -ln J = kappa* ln(p' / p'_0) + (lambda* - kappa*) ln(p_c / p_c0),
// with J the particle's volume ratio and p'_0 its geostatic mean stress; a particle that has yielded (p_c >
// p_c0) lies on its yield surface. Both are read from the frames: the preconsolidation pressure the law
// declares reaches them as a field of its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const fs::path scene =
    fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/geomechanics/oedometer.toml";
constexpr double M = 1.2, lambda_star = 0.1, kappa_star = 0.02, pc0 = 10e3;

struct Point {
  double p, q, pc, J;
};

/// Each particle of a frame by id: p' and q of its stress (xx yy zz xy yz xz), p_c and J.
std::map<long, Point> read_frame(const fs::path& file) {
  const std::vector<double> stress = vtp_array(file, "stress"),
                            pc = vtp_array(file, "preconsolidation_pressure"), J = vtp_array(file, "J"),
                            id = vtp_array(file, "id");
  std::map<long, Point> out;
  for (std::size_t k = 0; k < id.size(); ++k) {
    const double* s = &stress[6 * k];
    const double p = -(s[0] + s[1] + s[2]) / 3;
    const double q = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                      (s[2] - s[0]) * (s[2] - s[0])) +
                               3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
    out[std::lround(id[k])] = {p, q, pc[k], J[k]};
  }
  return out;
}

struct Outcome {
  double identity;         // the largest |ln J + kappa* ln(p'/p'_0) + (lambda* - kappa*) ln(p_c/p_c0)|
  double outside;          // the largest f / p_c^2 of a particle (f <= 0: on or inside its yield surface)
  std::size_t on_surface;  // particles with |f| / p_c^2 <= 1e-7
  double settlement;       // the largest -ln J
  std::size_t particles, yielded;
};

Outcome compress(const std::string& name, const std::string& args) {
  const fs::path dir = scratch("cam_clay", name);
  const int status = run_mpm(scene, "--out " + (dir / "out").string() + " " + args, dir / "log.txt");
  EXPECT_EQ(status, 0) << slurp(dir / "log.txt");
  std::vector<fs::path> frames;
  for (const auto& e : fs::directory_iterator(dir / "out"))
    if (e.path().extension() == ".vtp") frames.push_back(e.path());
  std::sort(frames.begin(), frames.end());
  EXPECT_GE(frames.size(), 2u);
  const std::map<long, Point> first = read_frame(frames.front()), last = read_frame(frames.back());
  Outcome o{};
  o.particles = last.size();
  for (const auto& [id, s] : last) {
    const Point& s0 = first.at(id);
    EXPECT_EQ(s0.pc, pc0);
    const double residual =
        std::log(s.J) + kappa_star * std::log(s.p / s0.p) + (lambda_star - kappa_star) * std::log(s.pc / pc0);
    o.identity = std::max(o.identity, std::abs(residual));
    o.settlement = std::max(o.settlement, -std::log(s.J));
    const double f = (s.q * s.q / (M * M) + s.p * (s.p - s.pc)) / (s.pc * s.pc);
    o.outside = std::max(o.outside, f);
    if (std::abs(f) <= 1e-7) ++o.on_surface;
    if (s.pc > pc0) ++o.yielded;
  }
  std::printf(
      "%s: %zu particles, %zu yielded, %zu on the surface, largest -ln J %.4f, identity %.3g, "
      "largest f %.3g\n",
      name.c_str(), o.particles, o.yielded, o.on_surface, o.settlement, o.identity, o.outside);
  fs::remove_all(dir);
  return o;
}

// The frames hold 9 significant digits (%.9g): no particle lies outside its yield surface by more than 1e-7
// of p_c^2, and most lie on it (740 of the 800 in both engines: the column is pressed onto its normal
// compression line). The identity differs from zero by what the engine's J is not: ln J accumulates ln det(I
// + dL) while the law sums tr(dL), a difference of about |dL|^2 / 2 a step, 0.23^2 / (2 x 2,800) = 9e-6 for
// the most compressed particle over the explicit run's 2,800 steps. Measured: 1.0e-5 (explicit) and 1.4e-5
// (implicit); asserted 5e-5.
void expect_cam_clay(const Outcome& o) {
  EXPECT_EQ(o.particles, 800u);
  EXPECT_GE(o.on_surface, o.particles / 2);
  EXPECT_GE(o.yielded, o.on_surface);
  EXPECT_GT(o.settlement, 0.2);
  EXPECT_LE(o.outside, 1e-7);
  EXPECT_LE(o.identity, 5e-5);
}

TEST(CamClayRuns, ExplicitOedometerKeepsTheVolumetricLaws) {
  expect_cam_clay(compress("explicit", ""));
}

TEST(CamClayRuns, ImplicitOedometerKeepsTheVolumetricLaws) {
  expect_cam_clay(compress("implicit", "--set 'simulation.integrator=\"implicit\"'"));
}

// The preconsolidation pressure is kept in checkpoints: a run stopped part way and restarted ends with the
// bits of one that was not, in both engines.
TEST(CamClayRuns, RestartsKeepTheBits) {
  // The first 0.5 s, stopped after the first particles yield (at about 0.38 s) and restarted.
  const std::string shorter = " --set simulation.end_time=0.5";
  for (const std::string engine : {"explicit", "implicit"}) {
    const std::string set =
        shorter + (engine == "implicit" ? " --set 'simulation.integrator=\"implicit\"'" : "");
    const fs::path dir = scratch("cam_clay_restart", engine);
    const fs::path whole = dir / "whole", parts = dir / "parts";
    ASSERT_EQ(run_mpm(scene, "--out " + whole.string() + set, dir / "log.txt"), 0) << slurp(dir / "log.txt");
    ASSERT_EQ(
        run_mpm(scene,
                "--out " + parts.string() + " --stop-after " + (engine == "implicit" ? "850" : "900") + set,
                dir / "log.txt"),
        0)
        << slurp(dir / "log.txt");
    ASSERT_EQ(
        run_mpm(scene, "--out " + parts.string() + " --restart " + (parts / "checkpoint.h5").string() + set,
                dir / "log.txt"),
        0)
        << slurp(dir / "log.txt");
    const std::string a = slurp(whole / "particles_0002.vtp"), b = slurp(parts / "particles_0002.vtp");
    EXPECT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << engine << ": the restarted run's last frame differs";
    fs::remove_all(dir);
  }
}

}  // namespace

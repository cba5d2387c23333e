// Frictional materials in whole runs (examples/geomechanics/unconfined-compression.toml): a Tresca block in
// plane-strain unconfined compression between smooth platens, with Mohr-Coulomb (phi = 0) and with
// Drucker-Prager's plane-strain cone (phi = 0: sqrt(J2) <= c), in the explicit and the implicit engine. The
// deformation is homogeneous, so once the block yields every particle carries sigma_yy = -2 c (sigma_xx = 0,
// the Tresca strength) and the platen's reaction is 2 c times the block's current half-width.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const fs::path scene = fs::path(__FILE__).parent_path().parent_path().parent_path() /
                       "examples/geomechanics/unconfined-compression.toml";
constexpr double c = 1e3, v = 0.01, ramp = 0.05, half_width = 0.2;

struct Outcome {
  double largest_tresca;  // the largest s1 - s3 of a particle at the end over 2 c
  double least_plastic;   // the smallest accumulated plastic strain of a particle at the end
  double
      mean_reaction;  // the platen's reaction over 2 c times the current half-width, averaged for t >= 0.1 s
};

Outcome compress(const std::string& name, const std::string& args) {
  const fs::path dir = scratch("geomaterials", name);
  const int status = run_mpm(scene, "--out " + (dir / "out").string() + " " + args, dir / "log.txt");
  EXPECT_EQ(status, 0) << slurp(dir / "log.txt");
  const auto h = csv_columns(dir / "out/history.csv");
  Outcome o{};
  int n = 0;
  for (std::size_t k = 0; k < h.at("time").size(); ++k) {
    const double t = h.at("time")[k];
    if (t < 0.1) continue;
    const double shortening = v * (ramp / 2 + t - ramp);
    const double width = half_width * half_width / (half_width - shortening);  // plastic flow keeps the area
    o.mean_reaction += -h.at("reaction_platen_y")[k] / (2 * c * width);
    ++n;
  }
  o.mean_reaction /= n;
  fs::path last;
  for (const auto& e : fs::directory_iterator(dir / "out"))
    if (e.path().extension() == ".vtp" && (last.empty() || e.path() > last)) last = e.path();
  const std::vector<double> stress = vtp_array(last, "stress"), plastic = vtp_array(last, "plastic_strain");
  const std::size_t particles = plastic.size();
  EXPECT_EQ(particles, 400u);
  for (std::size_t p = 0; p < particles; ++p) {  // stress: xx, yy, zz, xy, yz, xz
    const double* s = &stress[6 * p];
    const double centre = (s[0] + s[1]) / 2, radius = std::hypot((s[0] - s[1]) / 2, s[3]);
    const double s1 = std::max(centre + radius, s[2]), s3 = std::min(centre - radius, s[2]);
    o.largest_tresca = std::max(o.largest_tresca, (s1 - s3) / (2 * c));
  }
  o.least_plastic = *std::min_element(plastic.begin(), plastic.end());
  fs::remove_all(dir);
  return o;
}

// No particle's stress lies outside the Tresca hexagon (s1 - s3 <= 2 c; Drucker-Prager's sqrt(J2) <= c
// implies it), to round-off; every particle has yielded. The undamped block rings (the reaction swings by
// +-4%), so the reaction is averaged: it reads 0.990 to 0.991 of 2 c times the width whatever the kernel
// (cpgimp, linear), the cell size (h, h/2) or the platen's speed (v, v/4) in the explicit runs, while the
// particles' mean sigma_yy in a slow run is -2 c to 0.4%. That 1% lies in the force measured at the held
// nodes, not in the material; the assertion allows 2%.
void expect_tresca(const Outcome& o) {
  EXPECT_LE(o.largest_tresca, 1 + 1e-9);
  EXPECT_GT(o.least_plastic, 0) << "every particle has yielded";
  EXPECT_NEAR(o.mean_reaction, 1, 0.02);
}

TEST(Geomaterials, MohrCoulombBlockYieldsAtTheTrescaStrength) {
  expect_tresca(compress("mc", ""));
}

TEST(Geomaterials, DruckerPragerPlaneStrainConeGivesTheSameStrength) {
  expect_tresca(compress(
      "dp", "--set 'materials.0.model=\"drucker-prager\"' --set 'materials.0.match=\"plane-strain\"'"));
}

TEST(Geomaterials, TheImplicitEngineGivesTheSameStrength) {
  expect_tresca(compress("implicit", "--set 'simulation.integrator=\"implicit\"'"));
}

}  // namespace

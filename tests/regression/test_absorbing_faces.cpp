// Absorbing faces (Lysmer & Kuhlemeyer 1969 dashpots, grid.faces { absorbing = "MATERIAL" }):
// examples/geomechanics/absorbing-column.toml sends a P-wave pulse down a 1-D soil column into one; the
// energy left in the column once the pulse has passed is what the face reflected. A free face, for contrast,
// sends it all back.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const fs::path column = fs::path(__FILE__).parent_path().parent_path().parent_path() /
                        "examples/geomechanics/absorbing-column.toml";

/// The total energy in the column when the pulse has entered it (t = 0.1 s) and at the end (0.75 s, the pulse
/// having reached the x-max face at 0.545 s and left it by 0.6 s; a reflection would still be in the column).
struct Energies {
  double incident, left, input_work;
};
Energies pulse(const std::string& name, const std::string& args) {
  const fs::path dir = scratch("absorbing", name);
  const int status = run_mpm(column, "--out " + (dir / "out").string() + " " + args, dir / "log.txt");
  EXPECT_EQ(status, 0) << slurp(dir / "log.txt");
  const auto h = csv_columns(dir / "out/history.csv");
  Energies e{};
  for (std::size_t k = 0; k < h.at("time").size(); ++k)
    if (h.at("time")[k] <= 0.1) e.incident = h.at("total_energy")[k], e.input_work = h.at("external_work")[k];
  e.left = h.at("total_energy").back();
  fs::remove_all(dir);
  return e;
}

TEST(AbsorbingFaces, APWavePulseLeavesThroughTheDashpots) {
  const Energies e = pulse("absorbing", "");
  // The pulse carries the work the x-min face did (to 0.2%: the explicit step loses 0.15% over the run).
  EXPECT_NEAR(e.incident / e.input_work, 1, 0.002);
  // Measured: 0.107% of the incident energy comes back (the issue asks for less than 5%).
  EXPECT_LT(e.left / e.incident, 0.002);
}

TEST(AbsorbingFaces, AFreeFaceReflectsThePulse) {
  // Measured: 0.994 of the energy is back in the column (the reflection at the free end loses 0.6%).
  const Energies e = pulse("free", "--set 'grid.faces.x-max=\"free\"'");
  EXPECT_GT(e.left / e.incident, 0.99);
}

TEST(AbsorbingFaces, TheImplicitStepLetsThePulseOutToo) {
  // The dashpots in the implicit residual (-Z A v^L on the face's free unknowns, dt Z A on the tangent's
  // diagonal). At the explicit step size the implicit step itself dissipates: 0.879 of the x-min face's work
  // is in the column at t = 0.1 s, and with a free x-max face 0.577 of that is left at the end. With the
  // absorbing face 0.30% is left (measured; 0.57% at 4 times the step). Asserted: below 1%, and a free face
  // keeps over half.
  const std::string implicit = "--set simulation.integrator='\"implicit\"' ";
  const Energies absorbed = pulse("implicit", implicit);
  EXPECT_LT(absorbed.left / absorbed.incident, 0.01);
  const Energies reflected = pulse("implicit_free", implicit + "--set 'grid.faces.x-max=\"free\"'");
  EXPECT_GT(reflected.left / reflected.incident, 0.5);
}

}  // namespace

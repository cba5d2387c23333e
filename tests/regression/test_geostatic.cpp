// The K0 procedure ([[bodies]] k0, particles/geostatic.hpp): examples/geomechanics/k0-layer.toml, a
// Mohr-Coulomb layer 5 m deep under gravity from t = 0, starts in its geostatic stress and stays still; the
// same layer started unstressed falls under its weight and rings.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const fs::path layer =
    fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/geomechanics/k0-layer.toml";

/// The largest kinetic energy of a run of `scene` with `args` [J per m].
double largest_kinetic_energy(const fs::path& scene, const std::string& name, const std::string& args) {
  const fs::path dir = scratch("geostatic", name);
  const int status = run_mpm(scene, "--out " + (dir / "out").string() + " " + args, dir / "log.txt");
  EXPECT_EQ(status, 0) << slurp(dir / "log.txt");
  const std::vector<double> ke = csv_columns(dir / "out/history.csv").at("kinetic_energy");
  fs::remove_all(dir);
  return *std::max_element(ke.begin(), ke.end());
}

/// The layer without its k0 line: it starts unstressed.
double unstressed_kinetic_energy(const std::string& args) {
  const fs::path dir = scratch("geostatic", "scene");
  std::string text = slurp(layer);
  const std::size_t at = text.find("\nk0 = ");
  text.erase(at, text.find('\n', at + 1) - at);
  const fs::path scene = dir / "unstressed.toml";
  std::ofstream(scene) << text;
  const double ke = largest_kinetic_energy(scene, "unstressed", args);
  fs::remove_all(dir);
  return ke;
}

// The geostatic stress balances the particles' weight at every node to round-off with cpGIMP on a regular
// lattice, in both engines: measured 1.5e-28 J against 1.2e3 J unstressed (explicit), exactly 0 (implicit).
// The bound, 1e-20 of the unstressed run, leaves room for round-off well above what was measured.
TEST(Geostatic, AK0LayerStartsInEquilibriumExplicit) {
  const double unstressed = unstressed_kinetic_energy("");
  EXPECT_GT(unstressed, 1e3);
  EXPECT_LT(largest_kinetic_energy(layer, "explicit", ""), 1e-20 * unstressed);
}

TEST(Geostatic, AK0LayerStartsInEquilibriumImplicit) {
  const std::string implicit = "--set 'simulation.integrator=\"implicit\"'";
  const double unstressed = unstressed_kinetic_energy(implicit);
  EXPECT_GT(unstressed, 1e2);
  EXPECT_LT(largest_kinetic_energy(layer, "implicit", implicit), 1e-20 * unstressed);
}

}  // namespace

// Hertz's line contact on examples/contact/hertz-cylinder.toml: an elastic cylinder pressed onto a
// frictionless Coulomb wall by a slowly grown body force. Held at the load, the wall carries the cylinder's
// weight, and the contact half-width, twice the spread of the wall's normal force over its nodes
// (contact_spread, a / 2 for Hertz's semi-elliptic pressure), approaches Hertz's a = sqrt(4 P R / (pi E*)) as
// the grid is refined: its square at first order in the cell width.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "../regression/support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

// The source root from this file's path (the support header's own __FILE__ is relative to tests/regression).
const std::string scene =
    (fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/contact/hertz-cylinder.toml")
        .string();
constexpr double pi = 3.14159265358979323846, R = 1.0, E_star = 1e6 / (1 - 0.3 * 0.3);

/// Means over the held load (t >= 2 s) at `cells` cells per axis: the wall's force P and the half-width 2 w.
struct Held {
  double force, half_width;
};
Held hold(const std::string& cells) {
  const fs::path dir = scratch("contact_hertz", "cells" + cells.substr(0, cells.find(',')));
  const std::string args =
      "--set 'grid.cells=[" + cells + "]' --set output.every=2.5 --out " + (dir / "out").string();
  EXPECT_EQ(run_mpm(scene, args, dir / "log.txt"), 0) << slurp(dir / "log.txt");
  const auto h = csv_columns(dir / "out/history.csv");
  fs::remove_all(dir);
  Held held{0, 0};
  int n = 0;
  for (std::size_t k = 0; k < h.at("time").size(); ++k)
    if (h.at("time")[k] >= 2.0) {
      held.force += h.at("reaction_y-min_y")[k];
      held.half_width += 2 * h.at("contact_spread_y-min")[k];
      ++n;
    }
  held.force /= n;
  held.half_width /= n;
  return held;
}

TEST(ContactHertz, HalfWidthApproachesHertzWithRefinement) {
  // The load aims at a = 0.2 R: P = pi E* a^2 / (4 R) = 34,523 N/m. Measured with h = R/20 and R/40: mean
  // wall force -0.12% and +1.2% of it (the cylinder still rocks a little on the contact after the ramp);
  // half-width +84% and +47% of Hertz's for that force. The excess adds in quadrature: a^2 = a_Hertz^2 + c R
  // h with c = 1.91 and 1.89, the wall acting at every node the particles reach, which a circle within about
  // a cell of the plane does over a half-width sqrt(2 R h) (docs/contact.md). So a^2 converges to Hertz's at
  // first order in h (measured order 1.03); asserted: order > 0.8 and 1.5 < c < 2.5.
  const double target = pi * E_star * 0.2 * 0.2 / (4 * R);
  std::vector<double> error;
  for (const auto& [cells, h] : {std::pair<std::string, double>{"48, 44", R / 20}, {"96, 88", R / 40}}) {
    const Held held = hold(cells);
    EXPECT_NEAR(held.force, target, 0.03 * target) << cells;
    const double hertz = 4 * held.force * R / (pi * E_star);  // a_Hertz^2
    const double excess = held.half_width * held.half_width - hertz;
    EXPECT_GT(excess / (R * h), 1.5) << cells;
    EXPECT_LT(excess / (R * h), 2.5) << cells;
    error.push_back(excess / hertz);
  }
  EXPECT_GT(std::log2(error[0] / error[1]), 0.8);
}

}  // namespace

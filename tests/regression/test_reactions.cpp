// The reactions in history.csv beside symmetry planes and periodic faces (issue 47, item 11). A node beyond a
// symmetry plane is a mirror copy of a real node, and a node outside [0, cells - 1] on a periodic axis an
// image of one: the constraints hold them as they hold their originals, but a reaction that counted them
// would count the originals' forces twice. A block resting on a fixed floor between two symmetry planes
// reported 1.5 times its weight (4 columns of nodes, one ghost layer a side), 1.75 times on a periodic axis.
//
// Both tests use examples/block-on-floor's block (0.4 x 0.2 m, rubber, cpGIMP, 2 x 2 particles a cell), on a
// grid of 4 x 4 cells of 0.1 m whose sides are the faces under test, the block's bottom on the floor.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const fs::path block_scene =
    fs::path(__FILE__).parent_path().parent_path().parent_path() / "examples/block-on-floor/scene.toml";
constexpr double weight = 9.81 * 1000 * 0.4 * 0.2;  // [N/m]

/// The block on the floor, sides and floor as `faces` (a TOML inline table), with further --set arguments
/// `more` and `append`ed to the scene's text; the history's columns.
std::map<std::string, std::vector<double>> run_block(const std::string& name, const std::string& faces,
                                                     const std::string& more,
                                                     const std::string& append = "") {
  const fs::path dir = scratch("mpm_reactions", name);
  const fs::path scene = dir / "scene.toml";
  std::ofstream(scene) << slurp(block_scene) << append;
  const std::string wide =
      faces.find("x-max") == std::string::npos ? "0.8" : "0.4";  // one symmetry side: 8 cells
  const std::string args = "--quiet --set 'grid.hi=[" + wide + ",0.4]' --set 'grid.cells=[" +
                           (wide == "0.8" ? "8" : "4") +
                           ",4]' --set 'bodies.0.lo=[0,0]' --set 'bodies.0.hi=[0.4,0.2]'" +
                           " --set 'grid.faces=" + faces + "' " + more + " --out " + (dir / "out").string();
  EXPECT_EQ(run_mpm(scene, args, dir / "log"), 0) << name << ": " << slurp(dir / "log");
  std::map<std::string, std::vector<double>> h = csv_columns(dir / "out/history.csv");
  fs::remove_all(dir);
  return h;
}

/// sum over the steps of (the reactions' component c + the load g_c) dt, minus the change of momentum_c.
double balance(const std::map<std::string, std::vector<double>>& h, const std::string& c, double load) {
  const std::vector<double>& t = h.at("time");
  double impulse = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    double force = load;
    for (const auto& [name, values] : h)
      if (name.rfind("reaction_", 0) == 0 && name.substr(name.size() - 2) == "_" + c) force += values[k];
    impulse += force * (t[k] - t[k - 1]);
  }
  const std::vector<double>& p = h.at("momentum_" + c);
  return impulse - (p.back() - p.front());
}

TEST(Reactions, BesideSymmetryAndPeriodicFacesBalanceTheMomentum) {
  // Over 0.5 s of USL (no half step) and of the implicit step at Newton tolerance 1e-11, the sum of the
  // reactions and the weight, times dt, equals the particles' momentum change: the reaction is the force each
  // constraint applied, and G2P passes the nodal momentum change on exactly (SceneRun's FloorReaction test
  // without symmetry: ~1e-12 of the weight impulse). The copies counted, the residual was 0.25 to 0.75 of the
  // weight impulse; the absorbing floor, 0.9-1.3% of the momentum change. Tolerance: 1e-9 of the weight
  // impulse (or of the sinking block's momentum, 8 kg m/s per m, without gravity). Left out, measured: a
  // block beside one symmetry plane spreads, and particles' domains then reach past the plane, where the
  // mirror's share they gather counts in no reaction (docs/scene-format.md): 4e-9 of the weight impulse in y
  // with cpGIMP, 8e-6 in x with uGIMP; and the implicit step on a symmetry floor, off by 4e-5 of the weight
  // impulse in y (not yet explained).
  const std::string sym = "x-min = \"symmetry\", x-max = \"symmetry\"",
                    per = "x-min = \"periodic\", x-max = \"periodic\"";
  const std::string sinking = "--set 'loads.gravity=[0,0]' --set 'bodies.0.velocity=[0,-0.1]'";
  struct Case {
    std::string name, faces, more;
    bool implicit;
  };
  const std::vector<Case> cases = {
      {"fixed_sym", sym + ", y-min = \"fixed\"", "", true},
      {"fixed_per", per + ", y-min = \"fixed\"", "", true},
      {"coulomb_sym", sym + ", y-min = { friction = 0.3 }", "", false},
      {"coulomb_per", per + ", y-min = { friction = 0.3 }", "", false},
      {"symmetry_floor", sym + ", y-min = \"symmetry\"", "", false},
      {"absorbing_sym", sym + ", y-min = { absorbing = \"rubber\" }", sinking, true},
      {"absorbing_per", per + ", y-min = { absorbing = \"rubber\" }", sinking, true},
  };
  for (const Case& k : cases)
    for (const std::string integrator : {"usl", "implicit"}) {
      if (integrator == "implicit" && !k.implicit) continue;  // Coulomb walls are explicit only
      SCOPED_TRACE(k.name + ", " + integrator);
      const std::string more = k.more +
                               " --set simulation.end_time=0.5 --set simulation.integrator=" + integrator +
                               (integrator == "implicit" ? " --set implicit.newton_tolerance=1e-11" : "");
      const std::map<std::string, std::vector<double>> h =
          run_block(k.name + "_" + integrator, "{" + k.faces + "}", more);
      const bool gravity = k.more.empty();
      const double scale = gravity ? weight * 0.5 : 8.0;
      EXPECT_NEAR(balance(h, "y", gravity ? -weight : 0.0), 0, 1e-9 * scale);
      EXPECT_NEAR(balance(h, "x", 0.0), 0, 1e-9 * scale);
    }
}

TEST(Reactions, RigidBodiesBesideSymmetryAndPeriodicFacesBalanceTheMomentum) {
  // The block resting on a fixed rigid plate (y in [0, 0.1], the block raised onto it) instead of a grid
  // face: the plate's points reach the nodes beyond the side faces (a kernel's reach; with nodes = "inside",
  // the node on the periodic seam), copies whose reaction the plate counted. Measured before (USL): the
  // plate's mean reaction 1.50 times the weight with bspline2 between the planes, 1.25 on the periodic axis
  // (touched and inside), balances off by 0.50 and 0.25 of the weight impulse; a Coulomb plate's update at
  // the mirror nodes, not their real nodes' reflection, put it off by 1.4e-4. (cpGIMP's points reach no node
  // beyond the planes: that case held before.) The balance as in the test above, to 1e-9 of the weight
  // impulse; the floor face is free.
  const std::string sym = "x-min = \"symmetry\", x-max = \"symmetry\"",
                    per = "x-min = \"periodic\", x-max = \"periodic\"";
  const std::string plate =
      "\n[[rigid_bodies]]\nname = \"plate\"\nlo = [0.0, 0.0]\nhi = [0.4, 0.1]\nvelocity = [0.0, 0.0]\n";
  const std::string raised = " --set 'bodies.0.lo=[0,0.1]' --set 'bodies.0.hi=[0.4,0.3]'";
  struct Case {
    std::string name, faces, more, plate_keys;
    bool implicit;
  };
  const std::vector<Case> cases = {
      {"touched_sym", sym, "", "", true},
      {"touched_per", per, "", "", true},
      {"touched_bspline2_sym", sym, " --set simulation.kernel=bspline2", "", true},
      {"inside_per", per, "", "nodes = \"inside\"\n", true},
      {"coulomb_sym", sym, "", "friction = 0.3\n", false},
  };
  for (const Case& k : cases)
    for (const std::string integrator : {"usl", "implicit"}) {
      if (integrator == "implicit" && !k.implicit) continue;  // Coulomb bodies are explicit only
      SCOPED_TRACE(k.name + ", " + integrator);
      const std::string more = raised + k.more +
                               " --set simulation.end_time=0.5 --set simulation.integrator=" + integrator +
                               (integrator == "implicit" ? " --set implicit.newton_tolerance=1e-11" : "");
      const std::map<std::string, std::vector<double>> h =
          run_block("plate_" + k.name + "_" + integrator, "{" + k.faces + "}", more, plate + k.plate_keys);
      ASSERT_TRUE(h.count("reaction_plate_y"));
      EXPECT_NEAR(balance(h, "y", -weight), 0, 1e-9 * weight * 0.5);
      EXPECT_NEAR(balance(h, "x", 0.0), 0, 1e-9 * weight * 0.5);
    }
}

TEST(Reactions, ABlockAtRestBetweenSymmetryPlanesWeighsItsWeight) {
  // docs/scene-format.md's claim in the words: the floor's mean reaction over 1 s to 3 s of centered
  // difference is the block's weight. With the balance exact (the test above), mean reaction - weight is the
  // momentum change over those 2 s divided by 2 s; the ringing block's |p_y| stays below 0.131 kg m/s per m
  // there (measured), which bounds the difference at 1.7e-4 of the weight. Tolerance 1e-3 of the weight; the
  // copies counted, it was 1.5, 1.24 and 1.75 times the weight.
  for (const std::string faces : {"x-min = \"symmetry\", x-max = \"symmetry\"", "x-min = \"symmetry\"",
                                  "x-min = \"periodic\", x-max = \"periodic\""}) {
    SCOPED_TRACE(faces);
    const std::map<std::string, std::vector<double>> h =
        run_block("resting", "{" + faces + ", y-min = \"fixed\"}", "--set simulation.end_time=3");
    const std::vector<double>&t = h.at("time"), &r = h.at("reaction_y-min_y");
    double impulse = 0, span = 0;
    for (std::size_t k = 1; k < t.size(); ++k)
      if (t[k - 1] >= 1) {
        impulse += r[k] * (t[k] - t[k - 1]);
        span += t[k] - t[k - 1];
      }
    EXPECT_NEAR(impulse / span, weight, 1e-3 * weight);
  }
}

}  // namespace

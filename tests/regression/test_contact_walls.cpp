// Coulomb walls (a grid face with `friction`, contact/coulomb.hpp) on examples/contact/inclined-block.toml:
// an elastic block on a plane inclined by 30 degrees slides with the acceleration g (sin(theta) - mu
// cos(theta)) for mu < tan(theta) = 0.577 and stays put above it; while it slides the wall's tangential force
// is mu times its normal force; the energy balance closes with the dissipated energy; the same bits on 1 to 4
// ranks and after a restart; bad friction refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "distributed_support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mpm::testing;

const std::string block = (source_dir / "examples/contact/inclined-block.toml").string();
constexpr double g = 9.81, theta = 30 * 3.14159265358979323846 / 180, mass = 1000 * 0.4 * 0.2;  // [kg/m]

/// The history of the inclined block with friction mu (and more --set arguments).
std::map<std::string, std::vector<double>> slide(double mu, const std::string& more = "") {
  const fs::path dir = scratch("contact_walls", "mu" + std::to_string(mu));
  const int status = run_mpm(
      block, "--out " + (dir / "out").string() + " --set constants.mu=" + std::to_string(mu) + " " + more,
      dir / "log.txt");
  EXPECT_EQ(status, 0) << slurp(dir / "log.txt");
  std::map<std::string, std::vector<double>> h = csv_columns(dir / "out/history.csv");
  fs::remove_all(dir);
  return h;
}

/// The mean acceleration along the plane after the load's ramp (t >= 0.15 s): the change of momentum over
/// mass and time.
double acceleration(const std::map<std::string, std::vector<double>>& h) {
  const std::vector<double>& t = h.at("time");
  const std::vector<double>& p = h.at("momentum_x");
  std::size_t first = 0;
  while (t[first] < 0.15) ++first;
  return (p.back() - p[first]) / mass / (t.back() - t[first]);
}

TEST(ContactWalls, InclinedBlockSlidesWithTheCoulombAcceleration) {
  // Measured: mu = 0: exact to 1e-12 (a one-sided frictionless wall); 0.2: +0.7%; 0.4: -0.1% of the analytic
  // acceleration; asserted within 2%.
  for (double mu : {0.0, 0.2, 0.4}) {
    const auto h = slide(mu);
    const double expected = g * (std::sin(theta) - mu * std::cos(theta));
    EXPECT_NEAR(acceleration(h), expected, 0.02 * expected) << "mu = " << mu;
    // Sliding, every wall node gives mu times its normal force along the plane: so does the whole wall.
    const double normal = h.at("reaction_y-min_y").back(), tangential = h.at("reaction_y-min_x").back();
    EXPECT_GT(normal, 0.0);
    EXPECT_NEAR(tangential, -mu * normal, 1e-9 * normal) << "mu = " << mu;
    // Energy: kinetic + strain + dissipated = work of the loads (measured within 1.0%; the work and the
    // dissipation are each accounted to first order in the step).
    const double work = h.at("external_work").back();
    EXPECT_NEAR(h.at("total_energy").back() + h.at("friction_dissipation").back(), work, 0.02 * work)
        << "mu = " << mu;
    if (mu == 0) {
      EXPECT_EQ(h.at("friction_dissipation").back(), 0.0);
    }
  }
}

TEST(ContactWalls, InclinedBlockStaysPutAboveTanTheta) {
  // mu = 0.7 > tan(30 degrees): after the ramp the block does not move (measured |v| = 4e-4 m/s at 0.4 s,
  // where without friction it would move at 1.7 m/s).
  const auto h = slide(0.7);
  EXPECT_LT(std::abs(h.at("momentum_x").back() / mass), 2e-3);
  EXPECT_LT(std::abs(acceleration(h)), 0.01);
}

TEST(ContactWalls, TiltedGravityFromConstants) {
  // gravity as expressions of the constants, unramped: the block released onto the plane bounces on it, but
  // with mu = 0.2 it slides all the time, and its mean acceleration over the run is still the Coulomb one
  // (measured +0.3%).
  const auto h =
      slide(0.2,
            "--set 'loads.gravity=[\"g * sin(theta * pi / 180)\", \"-g * cos(theta * pi / 180)\"]' "
            "--set 'loads.body_force=[0.0, 0.0]'");
  const double expected = g * (std::sin(theta) - 0.2 * std::cos(theta));
  EXPECT_NEAR(h.at("momentum_x").back() / mass / h.at("time").back(), expected, 0.02 * expected);
}

TEST(ContactWalls, ACoulombRigidBodyActsAsTheWall) {
  // The plane made of a rigid body with friction (its normal from its points' shape-function gradients)
  // instead of the grid face: the block 0.1 m higher on a 0.1 m slab over the whole grid's width. The slab's
  // normal is vertical, so the block slides as on the face: measured the same acceleration to 1e-15.
  const fs::path dir = scratch("contact_walls", "rigid");
  std::string text = slurp(block);
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("hi = [2.0, 0.4]", "hi = [2.0, 0.5]");
  replace("cells = [80, 16]", "cells = [80, 20]");
  replace("faces = { y-min = { friction = \"mu\" } }", "faces = { y-min = \"fixed\" }");
  replace("lo = [0.1, 0.0]", "lo = [0.1, 0.1]");
  replace("hi = [0.5, 0.2]", "hi = [0.5, 0.3]");
  text +=
      "\n[[rigid_bodies]]\nname = \"plane\"\nlo = [0.0, 0.0]\nhi = [2.0, 0.1]\nvelocity = [0.0, "
      "0.0]\nfriction = \"mu\"\n";
  std::ofstream(dir / "rigid.toml") << text;
  ASSERT_EQ(run_mpm(dir / "rigid.toml", "--out " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  const auto h = csv_columns(dir / "out/history.csv");
  const double face = acceleration(slide(0.2));
  EXPECT_NEAR(acceleration(h), face, 1e-12 * face);
  const double normal = h.at("reaction_plane_y").back(), tangential = h.at("reaction_plane_x").back();
  EXPECT_GT(normal, 0.0);
  EXPECT_NEAR(tangential, -0.2 * normal, 1e-9 * normal);
  const double work = h.at("external_work").back();
  EXPECT_NEAR(h.at("total_energy").back() + h.at("friction_dissipation").back(), work, 0.02 * work);
  // A Coulomb body's contact follows its surface: contact_axes with it is refused, as is the implicit
  // integrator.
  for (const std::string& set : {std::string("--set 'rigid_bodies.0.contact_axes=[\"y\"]'"),
                                 std::string("--set simulation.integrator=implicit")}) {
    EXPECT_EQ(run_mpm(dir / "rigid.toml", "--out " + (dir / "bad").string() + " " + set, dir / "log.txt"), 2)
        << set;
    EXPECT_NE(slurp(dir / "log.txt").find("rigid_bodies[0].friction: "), std::string::npos)
        << slurp(dir / "log.txt");
  }
  fs::remove_all(dir);
}

TEST(ContactWalls, ASlabTiltedInUntiltedGravityActsAsTheInclinedWall) {
  // examples/contact/tilted-slab.toml to 0.6 s: the block on a polygon slab tilted by 30 degrees, a Coulomb
  // rigid body whose normal comes from its outline (RigidBody::outward), in untilted gravity. The elastic
  // block rocks on the slab after the ramp, and its normal force with it, so the acceleration along the slope
  // t = (cos theta, -sin theta) is the least-squares slope of its velocity over t >= 0.15 s. Measured against
  // g (sin theta - mu cos theta): -0.20%, -0.28%, -0.48% at mu = 0, 0.2, 0.4; the mean force along the
  // slab's normal n = (sin theta, cos theta) against m g cos theta: -0.19%, +0.50%, -0.81%, -0.20% (mu = 0.7,
  // where the block stays put). Asserted within 1%. While it slides, every node gives mu times its normal
  // force along the slope, and so does the whole slab.
  const std::string slab = (source_dir / "examples/contact/tilted-slab.toml").string();
  using Vec2 = std::array<double, 2>;
  const Vec2 along{std::cos(theta), -std::sin(theta)}, normal{std::sin(theta), std::cos(theta)};
  for (double mu : {0.0, 0.2, 0.4, 0.7}) {
    const fs::path dir = scratch("contact_walls", "slab" + std::to_string(mu));
    ASSERT_EQ(run_mpm(slab,
                      "--out " + (dir / "out").string() + " --set simulation.end_time=0.6" +
                          " --set rigid_bodies.0.friction=" + std::to_string(mu),
                      dir / "log.txt"),
              0)
        << slurp(dir / "log.txt");
    const auto h = csv_columns(dir / "out/history.csv");
    fs::remove_all(dir);
    const auto component = [&](const std::string& x, const std::string& y, const Vec2& e, std::size_t i) {
      return h.at(x)[i] * e[0] + h.at(y)[i] * e[1];
    };
    // Sums over the rows after the ramp: the mean normal force, and the least-squares line through the
    // velocity along the slope.
    double rows = 0, st = 0, sv = 0, stt = 0, stv = 0, pushed = 0;
    for (std::size_t i = 0; i < h.at("time").size(); ++i) {
      const double t = h.at("time")[i], v = component("momentum_x", "momentum_y", along, i) / mass;
      if (t < 0.15) continue;
      rows += 1, st += t, sv += v, stt += t * t, stv += t * v;
      pushed += component("reaction_slab_x", "reaction_slab_y", normal, i);
    }
    const double a = (rows * stv - st * sv) / (rows * stt - st * st), weight = mass * g * std::cos(theta);
    EXPECT_NEAR(pushed / rows, weight, 0.01 * weight) << "mu = " << mu;
    const std::size_t last = h.at("time").size() - 1;
    if (mu > std::tan(theta)) {
      EXPECT_LT(std::abs(component("momentum_x", "momentum_y", along, last) / mass), 2e-3);
      EXPECT_LT(std::abs(a), 0.01);
      continue;
    }
    const double expected = g * (std::sin(theta) - mu * std::cos(theta));
    EXPECT_NEAR(a, expected, 0.01 * expected) << "mu = " << mu;
    const double n = component("reaction_slab_x", "reaction_slab_y", normal, last);
    EXPECT_NEAR(component("reaction_slab_x", "reaction_slab_y", along, last), -mu * n, 1e-9 * n)
        << "mu = " << mu;
  }
}

/// An OBJ file of the prism over a quadrilateral of the xy-plane between z0 and z1.
void write_prism(const std::array<std::array<double, 2>, 4>& quad, double z0, double z1,
                 const fs::path& file) {
  std::ofstream os(file);
  os.precision(17);
  for (const double z : {z0, z1})
    for (const auto& [x, y] : quad) os << "v " << x << ' ' << y << ' ' << z << '\n';
  os << "f 1 2 3\nf 1 3 4\nf 5 7 6\nf 5 8 7\n";
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    os << "f " << i + 1 << ' ' << j + 1 << ' ' << j + 5 << "\nf " << i + 1 << ' ' << j + 5 << ' ' << i + 5
       << '\n';
  }
}

TEST(ContactWalls, ASlabOfTrianglesTiltedIn3DActsAsTheInclinedWall) {
  // The tilted slab in 3-D: the block and the slab are the 2-D example's outlines extruded along z (0.1 m and
  // 0.15 m) and read as triangulated surfaces (OBJ); the slab, a Coulomb rigid body, takes its normal from
  // its triangles (SurfaceNormal). h = 0.05 m, twice the 2-D example's; mu = 0.2. Measured, as in the 2-D
  // test: the acceleration along the slope 3.199 m/s^2, -0.21% of g (sin theta - mu cos theta), the mean
  // normal force within 0.01% of m g cos theta (with the slab's normal from its points' shape-function
  // gradients instead: -32.5% and +2.1%). Asserted within 1%.
  const fs::path dir = scratch("contact_walls", "slab3d");
  const double c = std::cos(theta), s = std::sin(theta);
  write_prism({{{0.2, 1.5},
                {0.2 + 2 * c, 1.5 - 2 * s},
                {0.2 + 2 * c - 0.15 * s, 1.5 - 2 * s - 0.15 * c},
                {0.2 - 0.15 * s, 1.5 - 0.15 * c}}},
              0.025, 0.175, dir / "slab.obj");
  const std::array<double, 2> corner{0.2 + 0.3 * c + 0.0 * s, 1.5 - 0.3 * s};
  write_prism({{corner,
                {corner[0] + 0.4 * c, corner[1] - 0.4 * s},
                {corner[0] + 0.4 * c + 0.2 * s, corner[1] - 0.4 * s + 0.2 * c},
                {corner[0] + 0.2 * s, corner[1] + 0.2 * c}}},
              0.05, 0.15, dir / "block.obj");
  std::ofstream(dir / "slab.toml") << R"toml([simulation]
dimension = 3
end_time = 0.6
integrator = "usl"
kernel = "cpgimp"
cfl = 0.4
[output]
every = 0.6
[grid]
lo = [0.0, 0.0, 0.0]
hi = [2.5, 2.0, 0.2]
cells = [50, 40, 4]
faces = { z-min = "symmetry", z-max = "symmetry" }
[[materials]]
name = "rubber"
E = 1.0e6
nu = 0.3
density = 1000.0
[[bodies]]
name = "block"
shape = "surface"
file = "block.obj"
[[rigid_bodies]]
name = "slab"
shape = "surface"
file = "slab.obj"
velocity = [0.0, 0.0, 0.0]
friction = 0.2
[loads]
body_force = [0.0, "-9.81 * min(t / 0.1, 1)", 0.0]
)toml";
  ASSERT_EQ(run_mpm(dir / "slab.toml", "--out " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  const auto h = csv_columns(dir / "out/history.csv");
  // The block's mass as seeded (its stair-stepped volume is not the prism's 8e-3 m^3).
  double mass3 = 0;
  for (const double m : vtp_array(dir / "out/particles_0000.vtp", "mass")) mass3 += m;
  fs::remove_all(dir);
  double rows = 0, st = 0, sv = 0, stt = 0, stv = 0, pushed = 0;
  for (std::size_t i = 0; i < h.at("time").size(); ++i) {
    const double t = h.at("time")[i], v = (h.at("momentum_x")[i] * c - h.at("momentum_y")[i] * s) / mass3;
    if (t < 0.15) continue;
    rows += 1, st += t, sv += v, stt += t * t, stv += t * v;
    pushed += h.at("reaction_slab_x")[i] * s + h.at("reaction_slab_y")[i] * c;
  }
  const double a = (rows * stv - st * sv) / (rows * stt - st * st), expected = g * (s - 0.2 * c);
  EXPECT_NEAR(a, expected, 0.01 * expected);
  EXPECT_NEAR(pushed / rows, mass3 * g * c, 0.01 * mass3 * g * c);
}

TEST(ContactWalls, SameBitsOnOneToFourRanks) {
  if (std::string(MPM_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI";
  std::vector<std::string> histories;
  for (int ranks = 1; ranks <= 4; ++ranks) {
    const fs::path dir = scratch("contact_walls", "ranks" + std::to_string(ranks));
    ASSERT_EQ(run_on(ranks, block, "--set simulation.end_time=0.15 --out " + (dir / "out").string(),
                     dir / "log.txt"),
              0)
        << slurp(dir / "log.txt");
    histories.push_back(slurp(dir / "out/history.csv"));
    fs::remove_all(dir);
  }
  EXPECT_NE(histories[0].find("friction_dissipation"), std::string::npos);
  for (int ranks = 2; ranks <= 4; ++ranks)
    EXPECT_EQ(histories[static_cast<std::size_t>(ranks - 1)], histories[0]) << ranks;
}

TEST(ContactWalls, RestartKeepsTheDissipation) {
  // Stopped after 300 steps and restarted from its checkpoint, the run ends with the uninterrupted history,
  // byte for byte, friction_dissipation included.
  const fs::path dir = scratch("contact_walls", "restart");
  const std::string end = "--set simulation.end_time=0.15 ";
  ASSERT_EQ(run_mpm(block, end + "--out " + (dir / "one").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(run_mpm(block, end + "--stop-after 300 --out " + (dir / "two").string(), dir / "log.txt"), 0);
  ASSERT_EQ(
      run_mpm(block,
              end + "--restart " + (dir / "two/checkpoint.h5").string() + " --out " + (dir / "two").string(),
              dir / "log.txt"),
      0)
      << slurp(dir / "log.txt");
  const std::string history = slurp(dir / "one/history.csv");
  EXPECT_GT(csv_columns(dir / "one/history.csv").at("friction_dissipation").back(), 0.0);
  EXPECT_EQ(slurp(dir / "two/history.csv"), history);
  fs::remove_all(dir);
}

TEST(ContactWalls, BadFrictionIsRefusedWithOneLine) {
  const fs::path dir = scratch("contact_walls", "bad");
  struct Case {
    std::string set, expected;
  };
  for (const Case& c : std::vector<Case>{
           {"--set constants.mu=-0.1", "grid.faces.y-min.friction: expected a friction coefficient >= 0"},
           {"--set simulation.integrator=implicit",
            "grid.faces.y-min.friction: Coulomb walls are for the explicit integrators"}}) {
    EXPECT_EQ(run_mpm(block, "--out " + (dir / "out").string() + " " + c.set, dir / "log.txt"), 2) << c.set;
    const std::string log = slurp(dir / "log.txt");
    EXPECT_NE(log.find(c.expected), std::string::npos) << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
  }
  fs::remove_all(dir);
}

}  // namespace

// Particle files that name their columns: each particle's material (by name or index), velocity, stress,
// plastic strain and its law's internal variables, as the scene seeds them, and a run in each engine that
// starts from them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {
namespace {

namespace fs = std::filesystem;

/// The "clay" material of scene_text: a rate-form solid without internal variables.
const char* const mohr_coulomb = R"(model = "mohr-coulomb"
E = 1e7
nu = 0.3
density = 1800.0
cohesion = 2e4
friction_angle = 0.0
)";

/// Two materials, a rate-form solid ("clay", of the keys given) and an elastic one, and one body from `file`
/// in a 1 x 1 m grid.
std::string scene_text(const std::string& integrator, const std::string& clay = mohr_coulomb,
                       const std::string& file = "cloud.csv") {
  return R"([simulation]
dimension = 2
end_time = 0.001
integrator = ")" +
         integrator + R"("
kernel = "bspline2"
cfl = 0.3
[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [10, 10]
[[materials]]
name = "clay"
)" + clay +
         R"([[materials]]
name = "stiff"
model = "hypoelastic"
E = 1e8
nu = 0.25
density = 2500.0
[[bodies]]
name = "cloud"
shape = "file"
file = ")" +
         file + "\"\n";
}

/// The file: a header naming the columns in any order, materials by name and by index.
const char* const cloud = R"(volume,material,x,y,vx,vy,sxx,syy,szz,sxy,plastic_strain
0.0025,clay,0.425,0.425,0.5,-0.25,-1000,-2000,-1500,300,0.01
0.0025,1,0.475,0.425,0.5,-0.25,-1100,-2100,-1600,310,0
0.0025,clay,0.425,0.475,0.5,-0.25,-1200,-2200,-1700,320,0.02
0.0025,stiff,0.475,0.475,0.5,-0.25,-1300,-2300,-1800,330,0
)";

struct Folder {
  fs::path path = fs::temp_directory_path() / ("mpm_test_particle_file_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path); }
  ~Folder() { fs::remove_all(path); }
};

TEST(ParticleFileColumns, GiveEachParticleItsMaterialVelocityAndStress) {
  const Folder dir;
  std::ofstream(dir.path / "cloud.csv") << cloud;
  const Scene sc = read_scene_text(scene_text("usl"), dir.path / "scene.toml");
  const ParticleSet<2> p = seed_bodies<2>(sc);
  ASSERT_EQ(p.size(), 4u);
  const std::uint16_t material[] = {0, 1, 0, 1};
  const double density[] = {1800, 2500, 1800, 2500};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(p.material[i], material[i]) << i;
    EXPECT_EQ(p.m[i], density[i] * 0.0025) << i;
    EXPECT_EQ(p.v[i], Vec<2>(0.5, -0.25)) << i;
    const double shift = -100.0 * static_cast<double>(i);  // each row's stresses 100 Pa lower
    EXPECT_EQ(p.state.sigma[i].c[0], -1000 + shift);       // xx
    EXPECT_EQ(p.state.sigma[i].c[1], -2000 + shift);       // yy
    EXPECT_EQ(p.state.sigma[i].c[2], -1500 + shift);       // zz
    EXPECT_EQ(p.state.sigma[i].c[3], 300 - shift / 10);    // xy
    EXPECT_EQ(p.state.sigma[i].c[4], 0.0);                 // xz and yz: not given
  }
  EXPECT_EQ(p.state.eps_bar[0], 0.01);
  EXPECT_EQ(p.state.eps_bar[2], 0.02);
  EXPECT_EQ(p.X[3], Vec<2>(0.475, 0.475));
}

TEST(ParticleFileColumns, StressForAnElasticSolidRefused) {
  const Folder dir;
  std::ofstream(dir.path / "cloud.csv") << "x,y,volume,sxx\n0.4,0.4,0.0025,-1000\n";
  std::string text = scene_text("usl");
  text.replace(text.find("model = \"hypoelastic\""), 21, "model = \"neo-hookean\"");
  text += "material = \"stiff\"\n";
  const Scene sc = read_scene_text(text, dir.path / "scene.toml");
  try {
    seed_bodies<2>(sc);
    FAIL() << "a stress for a Neo-Hookean particle was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cloud.csv:2: row of bodies[0].file in "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("material 'stiff' takes no initial stress or plastic strain"),
              std::string::npos)
        << e.what();
  }
}

/// The first data row of a history.csv: its columns by name.
std::map<std::string, double> first_row(const fs::path& file) {
  std::ifstream is(file);
  std::string header, row;
  std::getline(is, header);
  std::getline(is, row);
  std::stringstream hs(header), rs(row);
  std::map<std::string, double> out;
  for (std::string h, v; std::getline(hs, h, ',') && std::getline(rs, v, ',');) out[h] = std::stod(v);
  return out;
}

// Each engine starts from the file's velocities: the momentum at t = 0 is sum m v, 0.5 and -0.25 m/s times
// (1800 + 2500) x 2 x 0.0025 kg = 21.5 kg (to round-off).
TEST(ParticleFileColumns, BothEnginesStartFromTheFilesVelocities) {
  const Folder dir;
  std::ofstream(dir.path / "cloud.csv") << cloud;
  for (const std::string integrator : {"usl", "implicit"}) {
    std::ofstream(dir.path / "scene.toml") << scene_text(integrator);
    const fs::path out = dir.path / integrator;
    const std::string cmd = std::string(MPM_BINARY) + " run " + (dir.path / "scene.toml").string() +
                            " --quiet --out " + out.string() + " > " + (dir.path / "log").string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << integrator;
    const std::map<std::string, double> row = first_row(out / "history.csv");
    EXPECT_EQ(row.at("time"), 0.0);
    EXPECT_NEAR(row.at("momentum_x"), 0.5 * 21.5, 1e-12) << integrator;
    EXPECT_NEAR(row.at("momentum_y"), -0.25 * 21.5, 1e-12) << integrator;
  }
}

/// A modified Cam-Clay body from a file: each particle's stress and preconsolidation pressure, in a scene
/// whose material's own preconsolidation pressure is 200 kPa.
std::string cam_clay_scene(const std::string& integrator) {
  return scene_text(integrator, R"(model = "modified-cam-clay"
density = 1800.0
M = 1.2
compression_index = 0.1
swelling_index = 0.02
nu = 0.3
preconsolidation_pressure = 2e5
)",
                    "clay.csv");
}

/// Isotropic stresses of -50 kPa and -80 kPa; the first particle lightly, the second heavily
/// over-consolidated.
const char* const clay = R"(x,y,volume,material,sxx,syy,szz,preconsolidation_pressure
0.425,0.425,0.0025,clay,-5e4,-5e4,-5e4,1e5
0.475,0.425,0.0025,clay,-8e4,-8e4,-8e4,6e5
)";

// The file's preconsolidation pressures are each particle's initial internal variable, in both engines (the
// material's 200 kPa would be the value of a particle the file did not give one).
TEST(ParticleFileColumns, ALawsInternalVariablesComeFromTheFile) {
  const Folder dir;
  std::ofstream(dir.path / "clay.csv") << clay;
  const double expected[] = {1e5, 6e5};
  const Scene sc = read_scene_text(cam_clay_scene("usl"), dir.path / "scene.toml");
  const ParticleSet<2> p = seed_bodies<2>(sc);
  ASSERT_EQ(p.state.internal.size(), 2u);
  EXPECT_EQ(p.state.internal[0][0], 1e5);
  const Simulation<2, QuadraticBSplineKernel> explicit_run(make_spec<2>(sc), p);
  const Scene implicit_scene = read_scene_text(cam_clay_scene("implicit"), dir.path / "scene.toml");
  const ImplicitSimulation<2, QuadraticBSplineKernel> implicit_run(make_implicit_spec<2>(implicit_scene),
                                                                   seed_bodies<2>(implicit_scene));
  for (std::size_t i = 0; i < 2; ++i) {
    // The explicit engine sorts its particles by tile: find each by its reference position.
    const ParticleSet<2>& q = explicit_run.particles();
    for (std::size_t k = 0; k < q.size(); ++k)
      if (q.X[k] == p.X[i]) {
        EXPECT_EQ(q.state.internal[k][0], expected[i]) << "explicit, particle " << i;
      }
    EXPECT_EQ(implicit_run.state().internal[i][0], expected[i]) << "implicit, particle " << i;
  }
}

// A given preconsolidation pressure is checked as the material's is: the stress must lie inside the yield
// surface it bounds, and it must be positive; a law that keeps no such variable is refused at the row.
TEST(ParticleFileColumns, ALawsInternalVariablesFromTheFileAreChecked) {
  const Folder dir;
  const auto message = [&](const std::string& file_text) {
    std::ofstream(dir.path / "clay.csv") << file_text;
    try {
      const Scene sc = read_scene_text(cam_clay_scene("usl"), dir.path / "scene.toml");
      Simulation<2, QuadraticBSplineKernel> run(make_spec<2>(sc), seed_bodies<2>(sc));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string header = "x,y,volume,material,sxx,syy,szz,preconsolidation_pressure\n";
  std::string m = message(header +
                          "0.425,0.425,0.0025,clay,-5e4,-5e4,-5e4,1e5\n"
                          "0.475,0.425,0.0025,clay,-8e4,-8e4,-8e4,4e4\n");
  EXPECT_NE(
      m.find("materials[0]: particle 1 of a particle file: a particle of this modified-cam-clay material "
             "starts outside its yield surface (p' = 80000 Pa, q = 0 Pa, preconsolidation_pressure 40000 "
             "Pa): raise preconsolidation_pressure in the particle file"),
      std::string::npos)
      << m;
  m = message(header + "0.425,0.425,0.0025,clay,-5e4,-5e4,-5e4,-1e5\n");
  EXPECT_NE(
      m.find("particle 0 of a particle file: preconsolidation_pressure: expected a positive pressure [Pa], "
             "got -100000"),
      std::string::npos)
      << m;
  m = message(header + "0.425,0.425,0.0025,stiff,-5e4,-5e4,-5e4,1e5\n");
  EXPECT_NE(m.find("clay.csv:2: row of bodies[0].file in "), std::string::npos) << m;
  EXPECT_NE(m.find("material 'stiff' keeps no 'preconsolidation_pressure'"), std::string::npos) << m;
}

}  // namespace
}  // namespace mpm

namespace mpm {
namespace {

// A file of cubes one cell wide (one particle per cell) gives each the half-length h / 2 exactly: the cube
// root of h^3 is often the last bit above h (h = 0.1: 0.5 (10^-3)^(1/3) = 0.05000000000000001), which the
// GIMP kernels' bound h / 2 refused. The 3-D scene then runs with cpGIMP.
TEST(ParticleFile, CubesOneCellWideHaveHalfTheCellAsTheirHalfLength) {
  const Folder dir;
  {
    std::ofstream csv(dir.path / "cubes.csv");
    csv.precision(17);
    csv << "x,y,z,volume\n";
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i)
          csv << 0.45 + 0.1 * i << "," << 0.45 + 0.1 * j << "," << 0.45 + 0.1 * k << "," << 0.1 * 0.1 * 0.1
              << "\n";
  }
  std::ofstream(dir.path / "scene.toml") << R"([simulation]
dimension = 3
end_time = 1e-4
integrator = "usl"
kernel = "cpgimp"
cfl = 0.3
[grid]
lo = [0.0, 0.0, 0.0]
hi = [1.0, 1.0, 1.0]
cells = [10, 10, 10]
[[materials]]
name = "m"
E = 1e6
nu = 0.3
density = 1000.0
[[bodies]]
shape = "file"
file = "cubes.csv"
)";
  EXPECT_GT(0.5 * std::pow(0.1 * 0.1 * 0.1, 1.0 / 3), 0.05);  // the round-off this guards against
  const ParticleSet<3> p = seed_bodies<3>(read_scene(dir.path / "scene.toml"));
  ASSERT_EQ(p.size(), 8u);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p.half_length(i), Vec<3>::Constant(0.05));
  const std::string cmd = std::string(MPM_BINARY) + " run " + (dir.path / "scene.toml").string() +
                          " --quiet --out " + (dir.path / "out").string() + " > " +
                          (dir.path / "log").string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}

}  // namespace
}  // namespace mpm

// Particle files that name their columns: each particle's material (by name or index), velocity, stress and
// plastic strain, as the scene seeds them, and a run in each engine that starts from them.
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
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {
namespace {

namespace fs = std::filesystem;

/// Two materials, a rate-form solid and an elastic one, and one file body in a 1 x 1 m grid.
std::string scene_text(const std::string& integrator) {
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
model = "mohr-coulomb"
E = 1e7
nu = 0.3
density = 1800.0
cohesion = 2e4
friction_angle = 0.0
[[materials]]
name = "stiff"
model = "hypoelastic"
E = 1e8
nu = 0.25
density = 2500.0
[[bodies]]
name = "cloud"
shape = "file"
file = "cloud.csv"
)";
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

}  // namespace
}  // namespace mpm

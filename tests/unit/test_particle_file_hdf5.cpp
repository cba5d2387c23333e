// Particle files in HDF5: the root's 1-D datasets are the columns a CSV file's header names, and seed the
// same particles to the bit; a file that is not such a table is refused with one line naming it.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {
namespace {

namespace fs = std::filesystem;

struct Folder {
  fs::path path = fs::temp_directory_path() / ("mpm_test_particle_file_hdf5_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path); }
  ~Folder() { fs::remove_all(path); }
};

/// Write `columns` as datasets at the root of a new HDF5 file: doubles, or 32-bit integers for `material`;
/// `rank2` writes the first one as an n x 1 array instead.
void write_hdf5(const fs::path& file, const std::vector<std::pair<std::string, std::vector<double>>>& columns,
                bool rank2 = false) {
  const hid_t f = H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const auto& [name, values] = columns[k];
    const hsize_t dims[2] = {values.size(), 1};
    const hid_t space = H5Screate_simple(rank2 && k == 0 ? 2 : 1, dims, nullptr);
    const bool integer = name == "material";
    const hid_t set = H5Dcreate2(f, name.c_str(), integer ? H5T_STD_I32LE : H5T_IEEE_F64LE, space,
                                 H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<int> ints(values.begin(), values.end());
    EXPECT_GE(H5Dwrite(set, integer ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                       integer ? static_cast<const void*>(ints.data()) : values.data()),
              0);
    H5Dclose(set);
    H5Sclose(space);
  }
  H5Fclose(f);
}

/// A rate-form and an elastic material and one body from `file`, in a 1 x 1 m grid of 10 cells; of the
/// material `material` where the file gives none.
std::string scene_text(const std::string& file, const std::string& material = "") {
  return R"toml([simulation]
dimension = 2
end_time = 0.001
integrator = "usl"
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
[[materials]]
name = "stiff"
model = "hypoelastic"
E = 1e8
nu = 0.25
density = 2500.0
[[bodies]]
name = "cloud"
shape = "file"
file = ")toml" +
         file + "\"\n" + (material.empty() ? "" : "material = \"" + material + "\"\n");
}

/// Four particles with every kind of column, the values decimals that no double holds exactly.
const std::vector<std::pair<std::string, std::vector<double>>> cloud = {
    {"x", {0.425, 0.475, 0.425, 0.475}},
    {"y", {0.425, 0.425, 0.475, 0.475}},
    {"volume", {0.0025, 0.0025, 0.0025, 0.0025}},
    {"material", {0, 1, 0, 1}},
    {"vx", {0.1, 0.2, 0.3, 0.4}},
    {"sxx", {-1000.1, 0, -1200.3, 0}},
    {"sxy", {300.7, 0, 320.9, 0}},
    {"plastic_strain", {0.01, 0, 0.02, 0}},
};

TEST(ParticleFileHdf5, SeedsTheParticlesOfTheSameCsvFileToTheBit) {
  const Folder dir;
  write_hdf5(dir.path / "cloud.h5", cloud);
  {
    std::ofstream csv(dir.path / "cloud.csv");
    for (std::size_t k = 0; k < cloud.size(); ++k) csv << (k ? "," : "") << cloud[k].first;
    csv << "\n0.425,0.425,0.0025,0,0.1,-1000.1,300.7,0.01\n0.475,0.425,0.0025,1,0.2,0,0,0\n"
        << "0.425,0.475,0.0025,0,0.3,-1200.3,320.9,0.02\n0.475,0.475,0.0025,1,0.4,0,0,0\n";
  }
  const ParticleSet<2> h5 = seed_bodies<2>(read_scene_text(scene_text("cloud.h5"), dir.path / "scene.toml"));
  const ParticleSet<2> csv =
      seed_bodies<2>(read_scene_text(scene_text("cloud.csv"), dir.path / "scene.toml"));
  ASSERT_EQ(h5.size(), 4u);
  ASSERT_EQ(csv.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(h5.x[i], csv.x[i]) << i;
    EXPECT_EQ(h5.v[i], csv.v[i]) << i;
    EXPECT_EQ(h5.m[i], csv.m[i]) << i;
    EXPECT_EQ(h5.V0[i], csv.V0[i]) << i;
    EXPECT_EQ(h5.l0[i], csv.l0[i]) << i;
    EXPECT_EQ(h5.material[i], csv.material[i]) << i;
    EXPECT_EQ(h5.state.eps_bar[i], csv.state.eps_bar[i]) << i;
    for (int c = 0; c < 6; ++c) EXPECT_EQ(h5.state.sigma[i].c[c], csv.state.sigma[i].c[c]) << i;
  }
  EXPECT_EQ(h5.x[1], Vec<2>(0.475, 0.425));
  EXPECT_EQ(h5.v[2], Vec<2>(0.3, 0));
  EXPECT_EQ(h5.material[1], 1);
  EXPECT_EQ(h5.state.sigma[2].c[3], 320.9);
  EXPECT_EQ(h5.state.eps_bar[2], 0.02);
}

/// The message of a scene whose particle file is `file` as `write` left it, of `material` where the file
/// gives none.
template <class Write>
std::string refusal(const Folder& dir, const std::string& file, Write&& write,
                    const std::string& material = "") {
  write(dir.path / file);
  try {
    seed_bodies<2>(read_scene_text(scene_text(file, material), dir.path / "scene.toml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ParticleFileHdf5, AFileThatIsNoTableOfColumnsIsRefusedNamingIt) {
  const Folder dir;
  const std::string f = (dir.path / "p.h5").string();
  const auto expect_has = [](const std::string& what, const std::string& part) {
    EXPECT_NE(what.find(part), std::string::npos) << what;
  };
  expect_has(
      refusal(
          dir, "p.h5", [](const fs::path& p) { std::ofstream(p) << "x,y,volume\n0.5,0.5,0.01\n"; }, "clay"),
      f + ": cannot be read as HDF5");
  expect_has(refusal(
                 dir, "p.h5", [](const fs::path& p) { write_hdf5(p, cloud, true); }, "clay"),
             f + ": dataset 'x' is not a 1-D array of numbers");
  expect_has(refusal(
                 dir, "p.h5",
                 [](const fs::path& p) {
                   write_hdf5(p, {{"x", {0.5, 0.6}}, {"y", {0.5}}, {"volume", {0.01, 0.01}}});
                 },
                 "clay"),
             f + ": dataset 'y' holds 1 values, 'volume' 2");
  expect_has(refusal(
                 dir, "p.h5",
                 [](const fs::path& p) {
                   write_hdf5(p, {{"x", {0.5}}, {"y", {0.5}}, {"volume", {0.01}}, {"temperature", {1}}});
                 },
                 "clay"),
             f + ": unknown column 'temperature' (expected x, vx, y, vy, volume, material");
  expect_has(refusal(
                 dir, "p.h5",
                 [](const fs::path& p) {
                   write_hdf5(p, {{"x", {0.5}}, {"volume", {0.01}}});
                 },
                 "clay"),
             f + ": no column 'y' (the position)");
  expect_has(refusal(
                 dir, "p.h5",
                 [](const fs::path& p) {
                   write_hdf5(p, {{"x", {0.5}}, {"y", {0.5}}, {"volume", {-1}}});
                 },
                 "clay"),
             f + ": row 1: row of bodies[0].file in ");
}

}  // namespace
}  // namespace mpm

// Surface bodies: a closed triangulated surface's inside test, volume and centroid, the STL (ASCII and
// binary) and OBJ files a scene reads it from, and the particles seeded inside it, whose volume and centroid
// converge to the surface's as the spacing shrinks; a surface with a hole is refused with one line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/geometry/surface.hpp"
#include "mpm/geometry/surface_normal.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {
namespace {

namespace fs = std::filesystem;

/// The unit cube [0, 1]^3, two triangles a face, outward.
TriangleSurface unit_cube() {
  TriangleSurface s;
  for (int k = 0; k < 8; ++k) s.vertices.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  s.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

/// A sphere of radius r about c: an icosahedron whose triangles are split in four `levels` times, the new
/// vertices pushed out onto the sphere.
TriangleSurface icosphere(const Vec<3>& c, Real r, int levels) {
  const Real t = (1 + std::sqrt(5.0)) / 2;
  TriangleSurface s;
  for (const Vec<3>& v : {Vec<3>(-1, t, 0), Vec<3>(1, t, 0), Vec<3>(-1, -t, 0), Vec<3>(1, -t, 0),
                          Vec<3>(0, -1, t), Vec<3>(0, 1, t), Vec<3>(0, -1, -t), Vec<3>(0, 1, -t),
                          Vec<3>(t, 0, -1), Vec<3>(t, 0, 1), Vec<3>(-t, 0, -1), Vec<3>(-t, 0, 1)})
    s.vertices.push_back(v.normalized());
  s.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> middle;
    const auto mid = [&](std::int32_t a, std::int32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      if (const auto it = middle.find(key); it != middle.end()) return it->second;
      s.vertices.push_back((s.vertices[a] + s.vertices[b]).normalized());
      return middle[key] = static_cast<std::int32_t>(s.vertices.size() - 1);
    };
    std::vector<std::array<std::int32_t, 3>> faces;
    for (const auto& f : s.faces) {
      const std::int32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      faces.insert(faces.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    s.faces = faces;
  }
  for (Vec<3>& v : s.vertices) v = c + r * v;
  return s;
}

/// A torus about c, axis z, radii R (of the tube's centre line) and a (of the tube), on an n x m grid of
/// quadrilaterals split in two.
TriangleSurface torus(const Vec<3>& c, Real R, Real a, int n, int m) {
  TriangleSurface s;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const Real u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      s.vertices.push_back(c + Vec<3>((R + a * std::cos(v)) * std::cos(u),
                                      (R + a * std::cos(v)) * std::sin(u), a * std::sin(v)));
    }
  const auto at = [&](int i, int j) { return static_cast<std::int32_t>((i % n) * m + j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      s.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return s;
}

void write_binary_stl(const TriangleSurface& s, const fs::path& file) {
  std::ofstream os(file, std::ios::binary);
  char header[80] = "binary STL written by test_surface";
  os.write(header, 80);
  const auto count = static_cast<std::uint32_t>(s.faces.size());
  os.write(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : s.faces) {
    float values[12] = {};  // the normal (zero: readers recompute it), then the three vertices
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) values[3 + 3 * k + d] = static_cast<float>(s.vertices[f[k]][d]);
    os.write(reinterpret_cast<const char*>(values), sizeof values);
    const std::uint16_t attributes = 0;
    os.write(reinterpret_cast<const char*>(&attributes), 2);
  }
}

void write_ascii_stl(const TriangleSurface& s, const fs::path& file) {
  std::ofstream os(file);
  os.precision(9);
  os << "solid test\n";
  for (const auto& f : s.faces) {
    os << "facet normal 0 0 0\nouter loop\n";
    for (int k = 0; k < 3; ++k)
      os << "vertex " << static_cast<float>(s.vertices[f[k]][0]) << ' '
         << static_cast<float>(s.vertices[f[k]][1]) << ' ' << static_cast<float>(s.vertices[f[k]][2]) << '\n';
    os << "endloop\nendfacet\n";
  }
  os << "endsolid test\n";
}

void write_obj(const TriangleSurface& s, const fs::path& file) {
  std::ofstream os(file);
  os.precision(9);
  for (const Vec<3>& v : s.vertices)
    os << "v " << static_cast<float>(v[0]) << ' ' << static_cast<float>(v[1]) << ' '
       << static_cast<float>(v[2]) << '\n';
  for (const auto& f : s.faces) os << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
}

/// The file's surface as the engine reads it: the vertices in single precision, as the files hold them.
TriangleSurface as_read(TriangleSurface s) {
  for (Vec<3>& v : s.vertices)
    for (int d = 0; d < 3; ++d) v[d] = static_cast<float>(v[d]);
  return s;
}

/// A scene of one surface body read from `file` on a 2 m cube of 0.2 m cells.
std::string surface_scene(const fs::path& file, int ppc) {
  return R"([simulation]
dimension = 3
end_time = 0.01
integrator = "usl"
kernel = "bspline2"
cfl = 0.4
[grid]
lo = [0.0, 0.0, 0.0]
hi = [2.0, 2.0, 2.0]
cells = [10, 10, 10]
[[materials]]
name = "steel"
E = 2e11
nu = 0.3
density = 7800.0
[[bodies]]
name = "part"
shape = "surface"
file = ")" +
         file.string() + "\"\nppc = " + std::to_string(ppc) + "\n";
}

struct Folder {
  fs::path path = fs::temp_directory_path() / ("mpm_test_surface_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path); }
  ~Folder() { fs::remove_all(path); }
};

TEST(SurfaceGeometry, LinesThroughEdgesAndVerticesCrossOnce) {
  const TriangleSurface cube = unit_cube();
  EXPECT_NEAR(cube.volume(), 1.0, 1e-15);
  EXPECT_NEAR((cube.centroid() - Vec<3>(0.5, 0.5, 0.5)).norm(), 0, 1e-15);
  EXPECT_NEAR(cube.area(), 6.0, 1e-15);
  EXPECT_FALSE(closure_defect(cube));
  EXPECT_EQ(cube.crossings(0.5, 0.5), (std::vector<Real>{0, 1}));
  EXPECT_EQ(cube.crossings(0.3, 0.7), (std::vector<Real>{0, 1}));  // through the faces' diagonals' sides
  EXPECT_EQ(cube.crossings(0.5, 0.5).size() % 2, 0u);
  // On the faces' diagonals, edges and corners: twice or never, whatever the line meets.
  for (const Vec<2>& yz : {Vec<2>(0.25, 0.25), Vec<2>(0, 0.5), Vec<2>(1, 0.5), Vec<2>(0, 0), Vec<2>(1, 1),
                           Vec<2>(0.5, 1), Vec<2>(2, 0.5)})
    EXPECT_EQ(cube.crossings(yz[0], yz[1]).size() % 2, 0u) << yz.transpose();
  TriangleSurface holed = cube;
  holed.faces.pop_back();
  const auto defect = closure_defect(holed);
  ASSERT_TRUE(defect);
  EXPECT_NE(defect->find("belongs to 1 triangle"), std::string::npos) << *defect;
}

TEST(SurfaceGeometry, OutwardNormalIsTheSignedDistancesGradient) {
  // The unit cube, some triangles turned the other way round: off a face its normal (outside and inside),
  // off an edge or a corner the unit vector from it, on a face the face's normal turned outward.
  TriangleSurface cube = unit_cube();
  for (std::size_t k = 0; k < cube.faces.size(); k += 3) std::swap(cube.faces[k][0], cube.faces[k][1]);
  SurfaceNormal normal(cube);
  const Real r2 = std::sqrt(0.5), r3 = std::sqrt(1.0 / 3);
  struct Case {
    Vec<3> x, n;
  };
  for (const Case& c :
       {Case{{0.5, 0.4, 1.3}, {0, 0, 1}}, Case{{0.5, 0.4, 0.9}, {0, 0, 1}}, Case{{0.5, 0.4, 1.0}, {0, 0, 1}},
        Case{{0.3, -0.2, 0.6}, {0, -1, 0}}, Case{{0.1, 0.45, 0.5}, {-1, 0, 0}},
        Case{{1.2, 0.5, 1.2}, {r2, 0, r2}}, Case{{-0.5, -0.5, -0.5}, {-r3, -r3, -r3}},
        Case{{0.2, 0.3, 0.35}, {-1, 0, 0}}, Case{{0.5, 1.0, 0.5}, {0, 1, 0}}}) {
    const Vec<3> n = normal(c.x);
    EXPECT_NEAR((n - c.n).norm(), 0, 1e-15) << c.x.transpose() << ": " << n.transpose();
  }
  // A ball of 1280 triangles: the normal off it is radial to within its facets' tilt, the nearest found
  // among the buckets being the nearest of all.
  const TriangleSurface ball = icosphere(Vec<3>(1, 2, 3), 0.5, 3);
  SurfaceNormal radial(ball);
  for (const Vec<3>& x :
       {Vec<3>(1.7, 2.1, 3.2), Vec<3>(1.1, 2.0, 2.9), Vec<3>(0.2, 1.5, 3.6), Vec<3>(1, 2, 3.45)}) {
    const Vec<3> n = radial(x);
    const auto distance = [&](const Vec<3>& p) {  // to the surface, over every triangle
      Real d = std::numeric_limits<Real>::infinity();
      for (const auto& f : ball.faces)
        d = std::min(
            d, (p - closest_on_triangle(p, ball.vertices[f[0]], ball.vertices[f[1]], ball.vertices[f[2]]))
                   .norm());
      return d;
    };
    const bool in = (x - Vec<3>(1, 2, 3)).norm() < 0.5;
    EXPECT_NEAR(n.norm(), 1, 1e-14) << x.transpose();
    EXPECT_GT(n.dot((x - Vec<3>(1, 2, 3)).normalized()), 0.99) << x.transpose() << (in ? " inside" : "");
    // Stepping the nearest distance (found over every triangle) from x against the normal outside, along it
    // inside, lands on the surface.
    const Real d = distance(x);
    EXPECT_LT(distance(x - (in ? -d : d) * n), 1e-12) << x.transpose();
  }
}

TEST(SurfaceGeometry, WeldMergesEqualVertices) {
  TriangleSurface soup;  // each triangle its own three vertices, as an STL file lists them
  const TriangleSurface cube = unit_cube();
  for (const auto& f : cube.faces) {
    const auto base = static_cast<std::int32_t>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(cube.vertices[f[k]]);
    soup.faces.push_back({base, base + 1, base + 2});
  }
  EXPECT_TRUE(closure_defect(soup));
  EXPECT_EQ(weld(soup), 0u);
  EXPECT_EQ(soup.vertices.size(), 8u);
  EXPECT_FALSE(closure_defect(soup));
}

// The seeded volume and centroid against the surface's own (the triangles' volume, not the smooth shape's).
// Only the cells of the particle lattice (side s) that the surface cuts can be counted wrongly, each by at
// most s^3; a plane patch of area a with normal n cuts about a (|n_x| + |n_y| + |n_z|) / s^2 <= sqrt(3) a /
// s^2 of them, so |V - V_surface| <= sqrt(3) A s for a surface of area A, and the centroid moves by at most
// that times the body's diameter over V.
void expect_converging(const TriangleSurface& exact, const fs::path& file, Real diameter) {
  const Real volume = exact.volume(), area = exact.area();
  for (int ppc : {1, 2, 4}) {
    const ParticleSet<3> p = seed_bodies<3>(read_scene_text(surface_scene(file, ppc), "surface.toml"));
    Real V = 0;
    Vec<3> moment = Vec<3>::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) V += p.V0[i], moment += p.V0[i] * p.X[i];
    const Real s = 0.2 / ppc, bound = std::sqrt(3.0) * area * s;
    EXPECT_LE(std::abs(V - volume), bound) << file.filename() << ", ppc " << ppc << ": V " << V;
    EXPECT_LE((moment / V - exact.centroid()).norm(), bound / V * diameter)
        << file.filename() << ", ppc " << ppc;
  }
}

TEST(SurfaceBody, SphereFromABinaryStlConverges) {
  const Folder dir;
  const TriangleSurface sphere = icosphere({1.0, 0.9, 1.1}, 0.7, 4);  // 5120 triangles
  write_binary_stl(sphere, dir.path / "sphere.stl");
  const TriangleSurface read = as_read(sphere);
  EXPECT_NEAR(read.volume(), 4.0 / 3 * M_PI * std::pow(0.7, 3), 0.01 * read.volume());  // an inscribed mesh
  expect_converging(read, dir.path / "sphere.stl", 1.4);
}

TEST(SurfaceBody, TorusFromAnAsciiStlConverges) {
  const Folder dir;
  const TriangleSurface ring = torus({1.0, 1.0, 1.0}, 0.6, 0.25, 48, 24);
  write_ascii_stl(ring, dir.path / "torus.stl");
  const TriangleSurface read = as_read(ring);
  EXPECT_NEAR(read.volume(), 2 * M_PI * M_PI * 0.6 * 0.25 * 0.25, 0.02 * read.volume());
  expect_converging(read, dir.path / "torus.stl", 1.7);
}

TEST(SurfaceBody, ObjFileScaledAndTranslated) {
  const Folder dir;
  TriangleSurface cube = unit_cube();  // in millimetres: a 400 mm cube
  for (Vec<3>& v : cube.vertices) v *= 400;
  write_obj(cube, dir.path / "cube.obj");
  std::string text = surface_scene(dir.path / "cube.obj", 2);
  text += "scale = 0.001\ntranslate = [0.2, 0.4, 0.6]\n";
  const ParticleSet<3> p = seed_bodies<3>(read_scene_text(text, "cube.toml"));
  ASSERT_EQ(p.size(), 4u * 4 * 4);  // [0.2, 0.6] x [0.4, 0.8] x [0.6, 1.0]: 2 cells, 4 particles per axis
  Real V = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    V += p.V0[i];
    EXPECT_TRUE(p.X[i][0] > 0.2 && p.X[i][0] < 0.6 && p.X[i][1] > 0.4 && p.X[i][1] < 0.8 && p.X[i][2] > 0.6 &&
                p.X[i][2] < 1.0);
  }
  EXPECT_NEAR(V, 0.064, 1e-15);
}

// A surface as a cutter: the box [0.2, 1.0]^3 minus the cube [0.4, 0.8]^3 read from an OBJ file, every face
// on a line of the lattice (s = 0.1 m): 8^3 - 4^3 particles exactly, none inside the cube.
TEST(SurfaceBody, SubtractedFromABox) {
  const Folder dir;
  TriangleSurface cube = unit_cube();
  for (Vec<3>& v : cube.vertices) v = 0.4 * v + Vec<3>::Constant(0.4);
  write_obj(cube, dir.path / "hollow.obj");
  std::string text = surface_scene(dir.path / "hollow.obj", 2);
  const std::string shape_key = "shape = \"surface\"\nfile";
  text.replace(text.find(shape_key), shape_key.size(),
               "lo = [0.2, 0.2, 0.2]\nhi = [1.0, 1.0, 1.0]\nsubtract = [{ shape = \"surface\", file");
  text.replace(text.find("\nppc"), 4, " }]\nppc");
  const ParticleSet<3> p = seed_bodies<3>(read_scene_text(text, "hollow.toml"));
  EXPECT_EQ(p.size(), 512u - 64u);
  for (std::size_t i = 0; i < p.size(); ++i)
    EXPECT_FALSE((p.X[i].array() > 0.4).all() && (p.X[i].array() < 0.8).all()) << p.X[i].transpose();
}

TEST(SurfaceBody, HoleRefusedWithOneLine) {
  const Folder dir;
  TriangleSurface sphere = icosphere({1, 1, 1}, 0.5, 1);
  sphere.faces.erase(sphere.faces.begin() + 7);
  write_binary_stl(sphere, dir.path / "holed.stl");
  try {
    read_scene_text(surface_scene(dir.path / "holed.stl", 2), "holed.toml");
    FAIL() << "a surface with a hole was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("holed.toml:19: bodies[0].file: "), std::string::npos) << what;
    EXPECT_NE(what.find("holed.stl"), std::string::npos) << what;
    EXPECT_NE(what.find("the surface is not closed: the edge from ("), std::string::npos) << what;
    EXPECT_NE(what.find("belongs to 1 triangle"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(SurfaceBody, OtherFormatsRefused) {
  const Folder dir;
  write_obj(unit_cube(), dir.path / "cube.ply");
  try {
    read_scene_text(surface_scene(dir.path / "cube.ply", 2), "ply.toml");
    FAIL() << "a .ply file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected an .stl (ASCII or binary) or .obj file"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mpm

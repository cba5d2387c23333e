#pragma once
/// A simulation described by a scene file (TOML): every key is documented in docs/scene-format.md.
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/integrators/spec.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/scene/expression.hpp"

namespace mpm {

/// A grid face: free, fixed (zero velocity), symmetry plane, or a prescribed velocity v(t).
struct SceneFace {
  enum class Kind { free, fixed, symmetry, velocity } kind = Kind::free;
  std::vector<ExpressionPtr> velocity;  ///< one expression of t per component (kind == velocity)
};

struct SceneMaterial {
  std::string name;
  NeoHookean law;
};

/// A body of particles: a box, a disk (sphere in 3-D), a ring (annulus; spherical shell in 3-D), or a CSV file
/// of positions and volumes.
struct SceneBody {
  enum class Shape { box, disk, ring, file } shape = Shape::box;
  std::string name;
  std::vector<double> lo, hi;       ///< box corners [m]
  std::vector<double> center;       ///< disk and ring centre [m]
  double radius = 0;                ///< disk and outer ring radius [m]
  double inner_radius = 0;          ///< ring inner radius [m]
  std::filesystem::path file;       ///< particle file (shape == file)
  int ppc = 2;                      ///< particles per cell per axis (lattice shapes)
  std::size_t material = 0;         ///< index into Scene::materials
  std::vector<ExpressionPtr> velocity;      ///< initial velocity, expressions of x, y, z
  std::vector<ExpressionPtr> displacement;  ///< optional initial displacement u(X, Y, Z)
  std::vector<ExpressionPtr> deformation;   ///< optional initial F (row by row), expressions of X, Y, Z
};

/// A traction [Pa] on one face of a box body, carried by the body's outermost particle layer at that face.
struct SceneTraction {
  std::size_t body = 0;
  int face = 0;                         ///< 0..2*dim-1: x-min, x-max, y-min, ...
  std::vector<ExpressionPtr> traction;  ///< expressions of t
};

struct Scene {
  std::filesystem::path file;  ///< where it was read from (particle files are relative to it)
  std::string text;            ///< the scene file as read (stored in checkpoints)
  std::map<std::string, double> constants;

  // [simulation]
  int dim = 2;
  double end_time = 0;
  Integrator integrator = Integrator::usl;
  KernelKind kernel = KernelKind::linear;
  double gimp_length = 0;
  double dt = 0, cfl = 0;  ///< exactly one is positive
  int threads = 0;

  // [output]
  double output_every = 0;  ///< simulated time between particle outputs; 0: first and last only

  // [grid]
  std::vector<double> grid_lo, grid_hi;
  std::vector<int> cells;
  double h = 0;
  std::vector<SceneFace> faces;  ///< 2*dim faces: x-min, x-max, y-min, y-max, z-min, z-max
  ConstrainedAcceleration constrained_acceleration = ConstrainedAcceleration::zero;

  std::vector<SceneMaterial> materials;
  std::vector<SceneBody> bodies;

  // [loads]
  std::vector<double> gravity;
  std::vector<ExpressionPtr> body_force;  ///< expressions of X, Y, Z, t; empty: none
  std::vector<SceneTraction> tractions;

  // [check]
  std::vector<ExpressionPtr> exact_displacement;  ///< expressions of X, Y, Z, t; empty: no check
};

/// Read, override and validate a scene. `overrides` are "key.path=value" strings (--set) applied to the TOML
/// before validation, value in TOML syntax (a bare word is taken as a string). Throws InputError naming the
/// file, the line where known, the key, and what was expected.
Scene read_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

/// Names of the faces in the order of Scene::faces.
inline constexpr std::array<const char*, 6> face_names{"x-min", "x-max", "y-min", "y-max", "z-min", "z-max"};

}  // namespace mpm

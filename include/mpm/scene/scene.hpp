#pragma once
/// A simulation described by a scene file (TOML): every key is documented in docs/scene-format.md.
#include <array>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/contact/multi_field.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/geometry/polygon.hpp"
#include "mpm/geometry/surface.hpp"
#include "mpm/implicit/spec.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/scene/expression.hpp"

namespace mpm {

/// A grid face: free, fixed (zero velocity), symmetry plane, or a prescribed velocity v(t).
struct SceneFace {
  enum class Kind { free, fixed, symmetry, velocity, periodic, outflow, absorbing } kind = Kind::free;
  std::vector<ExpressionPtr> velocity;  ///< one expression of t per component (kind == velocity)
  double friction = -1;  ///< kind fixed or velocity: >= 0 a Coulomb wall with this coefficient; < 0 no slip
  std::string absorbs;   ///< kind absorbing: the material whose waves it lets out
  double normal_impedance = 0,
         shear_impedance = 0;  ///< kind absorbing: rho0 c_p and rho0 c_s of that material
};

/// A material: Neo-Hookean, a rate-form hypoelastic / von Mises law (Sulsky & Kaul 2004), or a Newtonian
/// fluid.
struct SceneMaterial {
  std::string name;
  double density = 0;  ///< [kg/m^3]
  Material law;
};

/// Where a body or a rigid body lies: a box, a disk (sphere in 3-D), a ring (annulus; spherical shell in
/// 3-D), a polygon (2-D) or a closed triangulated surface (3-D), seeded on a lattice of ppc points per cell
/// per axis; or, for a body, a CSV file of positions and volumes.
struct SceneShape {
  enum class Shape { box, disk, ring, polygon, surface, file, mesh } shape = Shape::box;
  std::vector<double> lo, hi;  ///< box corners [m]
  std::vector<double> center;  ///< disk and ring centre [m]
  double radius = 0;           ///< disk and outer ring radius [m]
  double inner_radius = 0;     ///< ring inner radius [m]
  Polygon polygon;             ///< a polygon's outline [m]
  TriangleSurface surface;     ///< a surface's triangles, scaled and moved [m]
  std::filesystem::path file;  ///< particle file (shape == file) or Gmsh mesh (shape == mesh)
  int ppc = 2;                 ///< points per cell per axis (lattice shapes)
};

/// A rigid body: material points in a SceneShape (not a file) moving at a prescribed velocity v(t).
struct SceneRigidBody : SceneShape {
  std::string name;
  std::vector<ExpressionPtr> velocity;  ///< expressions of t
  std::vector<bool> imposes;            ///< per axis: the body imposes this velocity component
  double friction = -1;                 ///< >= 0: a Coulomb body with this coefficient; < 0 no slip
  bool holds_inside = false;  ///< nodes = "inside": it holds the nodes in its box, not those it touches
};

/// A [[contact]] table: two groups of bodies (each a body, or several sharing one velocity field) that meet
/// by the Coulomb law of multi-field contact.
struct SceneContact {
  std::array<std::vector<std::size_t>, 2> groups;  ///< body indices of each side
  double friction = 0;                             ///< >= 0; infinity: "no-slip"
  ContactNormal normal = ContactNormal::average;
  double gap = std::numeric_limits<double>::infinity();  ///< [cells]; infinity: every approach is contact
};

/// The [implicit] table: the theta-blended Newton-Krylov step of Sulsky & Kaul 2004.
struct SceneImplicit {
  double theta = 1;
  Formulation formulation = Formulation::momentum;
  ImplicitSolver solver = ImplicitSolver::newton_gmres;
  numerics::NewtonSettings newton;
  bool frozen_jacobian = false;
  bool scaled_residual = true;  ///< residual = "scaled" (Sec. 3.2.2) or "unscaled"
  /// mass = "consistent" (Sulsky & Kaul 2004, Eq. (2.2.6)) or "lumped" (Sulsky & Kaul 2004, Eq. (2.2.12))
  bool consistent_mass = false;
  /// positions = "projected-velocity" (Sulsky & Kaul 2004, Eq. (3.2.7)) or "momentum" (Sulsky & Kaul 2004,
  /// Eq. (3.2.5))
  bool move_with_projected_velocity = false;
  double step_factor = 1, start_factor = 1, growth = 1.2;
  int max_retries = 8;
};

/// A particle of a mesh body: a Gauss point of one of the mesh's elements, the volume it stands for (its
/// weight times |det J|; per unit thickness in 2-D) and the material of the element's physical group.
struct MeshPoint {
  std::array<double, 3> x{};  ///< [m]
  double volume = 0;          ///< [m^3, or m^2 in 2-D]
  std::size_t material = 0;   ///< index into Scene::materials
};

/// A body of particles of one material, in a SceneShape combined with others: the points of its lattice that
/// lie in its shape or one of `add`, in every one of `intersect`, and in none of `subtract`.
struct SceneBody : SceneShape {
  std::string name;
  std::vector<SceneShape> add, subtract, intersect;  ///< lattice shapes, the body's ppc

  std::size_t material = 0;                 ///< index into Scene::materials (a file may give each particle's)
  std::vector<ExpressionPtr> velocity;      ///< initial velocity, expressions of x, y, z
  std::vector<ExpressionPtr> displacement;  ///< optional initial displacement u(X, Y, Z)
  std::vector<ExpressionPtr> deformation;   ///< optional initial F (row by row), expressions of X, Y, Z
  double k0 = -1;  ///< >= 0: the body starts in the geostatic stress of its weight with this K0
                   ///< (set_geostatic_stress)
  std::vector<MeshPoint> mesh_points;  ///< shape == mesh: its particles (read_mesh)
};

/// A traction [Pa] on one face of a box body, carried by the body's outermost particle layer at that face.
/// [[loads.traction]] or [[loads.pressure]]: a load on the surface of a body seeded on a lattice.
struct SceneSurfaceLoad {
  std::size_t body = 0;
  int face = -1;               ///< only the body's faces looking this way (x-min, x-max, ...); -1: all
  std::vector<double> lo, hi;  ///< only surface particles whose reference centre is in [lo, hi]; empty: all
  std::vector<ExpressionPtr> traction;  ///< a traction's components, expressions of t [Pa]
  ExpressionPtr pressure;               ///< a pressure, an expression of t [Pa]
};

struct Scene {
  std::filesystem::path file;          ///< where it was read from (particle files are relative to it)
  std::string text;                    ///< the scene file as read (stored in checkpoints)
  std::vector<std::string> overrides;  ///< the --set overrides applied to it, in order
  std::string
      resolved_text;  ///< the scene with the overrides applied, as TOML (the output's scene_as_run.toml)
  std::map<std::string, double> constants;

  // [simulation]
  int dim = 2;
  double end_time = 0;
  Integrator integrator = Integrator::usl;
  bool implicit = false;  ///< integrator = "implicit": the [implicit] table applies
  Geometry geometry = Geometry::plane_strain;
  KernelKind kernel = KernelKind::linear;
  /// uGIMP smoothing length l, the full particle width the kernel uses (Steffen et al. 2008, Sec. 4.1: l = 0
  /// is linear MPM, which the reader selects, l = h gives the quadratic B-spline); absent: each particle's
  /// own size.
  std::optional<double> gimp_length;
  double dt = 0, cfl = 0;  ///< exactly one is positive
  int threads = 0;
  bool reproject_light_nodes =
      true;                  ///< light_nodes = "reproject" (see SimulationSpec::reproject_light_nodes)
  double local_damping = 0;  ///< SimulationSpec::local_damping
  double flip_fraction = 1;  ///< [simulation] transfer = "flip": SimulationSpec::flip_fraction
  Transfer transfer = Transfer::flip;  ///< [simulation] transfer: SimulationSpec::transfer

  // [output]
  double output_every = 0;  ///< simulated time between particle outputs; 0: first and last only
  bool newton_log = false;  ///< newton_log = "on": newton.csv, ||F|| at each Newton iterate (implicit runs)

  // [grid]
  std::vector<double> grid_lo, grid_hi;
  std::vector<int> cells;
  double h = 0;
  std::vector<SceneFace> faces;  ///< 2*dim faces: x-min, x-max, y-min, y-max, z-min, z-max
  ConstrainedAcceleration constrained_acceleration = ConstrainedAcceleration::zero;

  std::vector<SceneMaterial> materials;
  std::vector<SceneBody> bodies;
  std::vector<SceneRigidBody> rigid_bodies;
  std::vector<SceneContact> contacts;
  /// The velocity field of each body (ParticleSet::field): 0 for all without [[contact]]; otherwise the
  /// bodies no table names share field 0, and each group named has a field of its own.
  std::vector<int> body_field;
  int fields = 1;
  SceneImplicit implicit_step;

  // [loads]
  std::vector<double> gravity;
  std::vector<ExpressionPtr> body_force;  ///< expressions of X, Y, Z, t; empty: none
  std::vector<SceneSurfaceLoad> surface_loads;

  // [check]
  std::vector<ExpressionPtr> exact_displacement;  ///< expressions of X, Y, Z, t; empty: no check
};

/// Read, override and validate a scene. `overrides` are "key.path=value" strings (--set) applied to the TOML
/// before validation, value in TOML syntax (a bare word is taken as a string). Throws InputError naming the
/// file, the line where known, the key, and what was expected.
Scene read_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
/// The scene's material laws, in the order of its [[materials]] tables.
inline std::vector<Material> material_laws(const Scene& sc) {
  std::vector<Material> laws;
  for (const SceneMaterial& m : sc.materials) laws.push_back(m.law);
  return laws;
}
/// The same for a scene's text: `file` names it in messages, and particle files are relative to its folder.
Scene read_scene_text(const std::string& text, const std::filesystem::path& file,
                      const std::vector<std::string>& overrides = {});

/// Names of the faces in the order of Scene::faces.
inline constexpr std::array<const char*, 6> face_names{"x-min", "x-max", "y-min", "y-max", "z-min", "z-max"};

}  // namespace mpm

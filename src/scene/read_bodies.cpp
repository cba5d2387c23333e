// Reading the bodies, rigid bodies and loads of a scene.
#include <filesystem>
#include <system_error>

#include "mpm/scene/budget.hpp"
#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// Empty when [lo, hi] lies inside the grid, else "lo" or "hi" (the side that leaves it).
std::string outside_grid(const Scene& sc, const std::vector<double>& lo, const std::vector<double>& hi) {
  for (int d = 0; d < sc.dim; ++d)
    if (lo[d] < sc.grid_lo[d] - 1e-12) return "lo";
  for (int d = 0; d < sc.dim; ++d)
    if (hi[d] > sc.grid_hi[d] + 1e-12) return "hi";
  return "";
}

/// The grid's extent for messages, e.g. "[0, 1] x [0, 2]".
std::string grid_extent(const Scene& sc) {
  std::ostringstream os;
  for (int d = 0; d < sc.dim; ++d) os << (d ? " x [" : "[") << sc.grid_lo[d] << ", " << sc.grid_hi[d] << "]";
  return os.str();
}

/// The corners `lo` and `hi` of a box inside the grid, each component a number or an expression of the
/// constants; `what` names it in the message ("the box").
void read_box(const Section& s, const Scene& sc, const std::string& what, std::vector<double>& lo,
              std::vector<double>& hi) {
  const auto n = static_cast<std::size_t>(sc.dim);
  lo = s.constant_numbers("lo", n, sc.constants);
  hi = s.constant_numbers("hi", n, sc.constants);
  for (std::size_t d = 0; d < n; ++d)
    if (!(hi[d] > lo[d])) s.fail("hi", "expected hi > lo on every axis");
  const std::string side = outside_grid(sc, lo, hi);
  if (!side.empty()) s.fail(side, what + " must lie inside the grid " + grid_extent(sc));
}
}  // namespace

void read_body(const Section& s, Scene& sc, std::size_t index) {
  const auto n = static_cast<std::size_t>(sc.dim);
  SceneBody b;
  b.name = s.name("name", "body " + std::to_string(index));
  const std::string shape = s.choice("shape", "box", {"box", "disk", "sphere", "ring", "polygon", "file"});
  if (shape == "box") {
    b.shape = SceneBody::Shape::box;
    read_box(s, sc, "the box", b.lo, b.hi);
  } else if (shape == "polygon") {
    if (sc.dim != 2) s.fail("shape", "\"polygon\" is for 2-D scenes");
    b.shape = SceneBody::Shape::polygon;
    b.polygon = read_outline(s, sc);
    const auto [lo, hi] = b.polygon.bounds();
    if (!outside_grid(sc, {lo[0], lo[1]}, {hi[0], hi[1]}).empty())
      s.fail("vertices", "the polygon must lie inside the grid " + grid_extent(sc));
  } else if (shape == "file") {
    b.shape = SceneBody::Shape::file;
    b.file = s.text("file", "");
    if (b.file.empty()) s.fail("file", "missing (a CSV file of positions and volumes)");
    if (b.file.is_relative()) b.file = sc.file.parent_path() / b.file;
    std::error_code ec;  // a name the file system refuses (too long, say) is an error, not an exception
    const std::filesystem::file_status status = std::filesystem::status(b.file, ec);
    if (!std::filesystem::exists(status))
      s.fail("file", "cannot open " + in_quotes(b.file.string()) + (ec ? " (" + ec.message() + ")" : ""));
    if (!std::filesystem::is_regular_file(status))
      s.fail("file",
             in_quotes(b.file.string()) + " is not a regular file (a CSV file of positions and volumes)");
  } else {
    if ((shape == "disk" && sc.dim != 2) || (shape == "sphere" && sc.dim != 3))
      s.fail("shape", "\"disk\" is for 2-D scenes, \"sphere\" for 3-D");
    if (shape == "ring" && sc.dim == 1) s.fail("shape", "\"ring\" needs a 2-D or 3-D scene");
    b.shape = shape == "ring" ? SceneBody::Shape::ring : SceneBody::Shape::disk;
    b.center = s.numbers("center", n);
    b.radius = s.required_number("radius");
    if (!(b.radius > 0)) s.fail("radius", "expected a positive radius [m]");
    if (b.shape == SceneBody::Shape::ring) {
      b.inner_radius = s.required_number("inner_radius");
      if (!(b.inner_radius >= 0 && b.inner_radius < b.radius))
        s.fail("inner_radius", "expected 0 <= inner_radius < radius");
    }
    std::vector<double> lo = b.center, hi = b.center;
    for (std::size_t d = 0; d < n; ++d) lo[d] -= b.radius, hi[d] += b.radius;
    if (!outside_grid(sc, lo, hi).empty())
      s.fail("radius", "the " + shape + " (center +- radius) must lie inside the grid " + grid_extent(sc));
  }
  b.ppc = s.integer("ppc", 2);
  if (b.ppc < 1 || b.ppc > limits::max_ppc)
    s.fail("ppc", "expected at least 1 and at most " + std::to_string(limits::max_ppc) +
                      " particles per cell per axis");
  const std::string material = s.text("material", sc.materials.size() == 1 ? sc.materials[0].name : "");
  if (material.empty()) s.fail("material", "missing (the name of a [[materials]] entry)");
  auto found = std::find_if(sc.materials.begin(), sc.materials.end(),
                            [&](const SceneMaterial& m) { return m.name == material; });
  if (found == sc.materials.end()) {
    std::vector<std::string> names;
    for (const SceneMaterial& m : sc.materials) names.push_back(m.name);
    s.fail("material", "no material named " + in_quotes(material) + " (defined: " + join(names) + ")");
  }
  b.material = static_cast<std::size_t>(found - sc.materials.begin());
  if (s.has("velocity")) b.velocity = s.expressions("velocity", n, position_vars[n - 1], sc.constants);
  if (s.has("displacement"))
    b.displacement = s.expressions("displacement", n, reference_vars[n - 1], sc.constants);
  if (s.has("deformation_gradient")) {
    if (!s.has("displacement")) s.fail("deformation_gradient", "needs the matching initial displacement");
    b.deformation = s.expressions("deformation_gradient", n * n, reference_vars[n - 1], sc.constants);
  }
  if (s.has("k0")) {
    b.k0 = s.constant_number("k0", 0, sc.constants);
    if (!(b.k0 >= 0)) s.fail("k0", "expected a lateral stress ratio K0 >= 0");
    const Material& law = sc.materials[b.material].law;
    if (!is_rate_form(law) || std::holds_alternative<NewtonianFluid>(law))
      s.fail(
          "k0",
          "a geostatic stress needs a rate-form solid (hypoelastic, von-mises, drucker-prager, mohr-coulomb, "
          "modified-cam-clay); "
          "material " +
              in_quotes(material) + " is not one");
    if (!b.displacement.empty())
      s.fail("k0", "a body in geostatic stress starts undisplaced; drop displacement");
  }
  sc.bodies.push_back(std::move(b));
}

namespace {
/// One [[loads.traction]] or [[loads.pressure]] table.
void read_surface_load(const Section& t, const std::string& kind, Scene& sc, const Locator& loc) {
  const auto n = static_cast<std::size_t>(sc.dim);
  SceneSurfaceLoad load;
  if (!t.has("body")) t.fail("body", "missing (the name of the loaded body)");
  const std::string body = t.text("body", "");
  auto found =
      std::find_if(sc.bodies.begin(), sc.bodies.end(), [&](const SceneBody& b) { return b.name == body; });
  if (found == sc.bodies.end()) t.fail("body", "no body named " + in_quotes(body));
  if (found->shape == SceneBody::Shape::file)
    t.fail("body",
           "surface loads need a body seeded on a lattice (box, disk, sphere or ring), not a particle file");
  load.body = static_cast<std::size_t>(found - sc.bodies.begin());
  if (t.has("face")) {
    const std::vector<std::string> names(face_names.begin(), face_names.begin() + 2 * sc.dim);
    const std::string face = t.choice("face", "", names);
    load.face = static_cast<int>(std::find(names.begin(), names.end(), face) - names.begin());
  }
  if (const toml::table* region = t.table("region")) {
    const Section r(*region, t.key_of("region"), loc, {"lo", "hi"});
    read_box(r, sc, "the region", load.lo, load.hi);
  }
  if (kind == "traction") {
    load.traction = t.expressions("traction", n, time_var, sc.constants);
  } else {
    if (sc.geometry == Geometry::plane_stress)
      t.fail("pressure",
             "a follower pressure needs the thickness's change, which plane stress does not follow; "
             "use plane strain, axisymmetry or 3-D");
    load.pressure = t.expression("pressure", time_var, sc.constants);
  }
  sc.surface_loads.push_back(std::move(load));
}
}  // namespace

void read_loads(const Section& s, Scene& sc, const Locator& loc) {
  const auto n = static_cast<std::size_t>(sc.dim);
  sc.gravity =
      s.has("gravity") ? s.constant_numbers("gravity", n, sc.constants) : std::vector<double>(n, 0.0);
  if (s.has("body_force"))
    sc.body_force = s.expressions("body_force", n, reference_time_vars[n - 1], sc.constants);
  for (const std::string kind : {"traction", "pressure"}) {
    const std::vector<const toml::table*> loads = s.tables(kind);
    for (std::size_t k = 0; k < loads.size(); ++k)
      read_surface_load(Section(*loads[k], s.key_of(kind + "[" + std::to_string(k) + "]"), loc,
                                {"body", "face", "region", kind}),
                        kind, sc, loc);
  }
}

void read_rigid_body(const Section& s, Scene& sc, std::size_t index) {
  const auto n = static_cast<std::size_t>(sc.dim);
  SceneRigidBody r;
  r.name = s.name("name", "rigid " + std::to_string(index));
  s.choice("shape", "box", {"box"});
  read_box(s, sc, "the rigid body", r.lo, r.hi);
  r.ppc = s.integer("ppc", 2);
  if (r.ppc < 1 || r.ppc > limits::max_ppc)
    s.fail("ppc", "expected at least 1 and at most " + std::to_string(limits::max_ppc) +
                      " points per cell per axis");
  if (!s.has("velocity"))
    s.fail("velocity", "missing (the prescribed velocity, numbers or expressions of t)");
  r.velocity = s.expressions("velocity", n, time_var, sc.constants);
  r.imposes.assign(n, !s.has("contact_axes"));
  if (s.has("contact_axes")) {
    static const std::vector<std::string> axes{"x", "y", "z"};
    const toml::array& a = s.array("contact_axes", 0, "an array of axis names (\"x\", \"y\", \"z\")");
    for (const toml::node& e : a) {
      const auto axis = std::find(axes.begin(), axes.begin() + sc.dim, e.value<std::string>().value_or(""));
      if (axis == axes.begin() + sc.dim)
        s.fail("contact_axes", "expected axis names of this dimension, got " + describe(e));
      r.imposes[static_cast<std::size_t>(axis - axes.begin())] = true;
    }
  }
  if (s.has("friction")) {
    if (s.has("contact_axes"))
      s.fail("friction", "a Coulomb body's contact follows its surface; drop contact_axes");
    if (sc.implicit)
      s.fail("friction",
             "Coulomb bodies are for the explicit integrators; the implicit one holds every component "
             "a rigid body touches");
    r.friction = s.constant_number("friction", 0.0, sc.constants);
    if (!(r.friction >= 0))
      s.fail("friction", "expected a friction coefficient >= 0, got " + std::to_string(r.friction));
  }
  r.holds_inside = s.choice("nodes", "touched", {"touched", "inside"}) == "inside";
  if (r.holds_inside && r.friction >= 0)
    s.fail(
        "nodes",
        "a Coulomb body's normals come from the nodes its points touch; drop nodes = \"inside\" or friction");
  sc.rigid_bodies.push_back(std::move(r));
}

}  // namespace mpm::scene_reading

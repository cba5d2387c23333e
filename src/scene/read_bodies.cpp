// Reading the bodies, rigid bodies and loads of a scene.
#include <filesystem>
#include <map>
#include <optional>
#include <system_error>

#include "mpm/scene/budget.hpp"
#include "particle_file.hpp"
#include "section.hpp"

namespace mpm::scene_reading {

void read_body(const Section& s, Scene& sc, std::size_t index) {
  const auto n = static_cast<std::size_t>(sc.dim);
  SceneBody b;
  b.name = s.name("name", "body " + std::to_string(index));
  read_shape(s, sc, "the box", ShapeOwner::body, b);
  for (auto [key, shapes] :
       {std::pair{"add", &b.add}, {"subtract", &b.subtract}, {"intersect", &b.intersect}}) {
    const std::vector<const toml::table*> tables = s.tables(key);
    if (!tables.empty() && (b.shape == SceneBody::Shape::file || b.shape == SceneBody::Shape::mesh))
      s.fail(key, "a particle file's or a mesh's body is not combined with shapes");
    for (std::size_t k = 0; k < tables.size(); ++k) {
      const Section t = s.below(*tables[k], std::string(key) + "[" + std::to_string(k) + "]",
                                {"shape", "lo", "hi", "center", "radius", "inner_radius", "vertices", "file",
                                 "scale", "translate"});
      shapes->push_back({});
      read_shape(t, sc, "the box", ShapeOwner::body_part, shapes->back());
      shapes->back().ppc = b.ppc;
    }
  }
  // A particle file may give each particle's material, velocity and stress in columns its header names.
  std::vector<ParticleColumn> columns;
  if (b.shape == SceneBody::Shape::file) {
    try {
      columns = particle_file_columns(b.file, sc.dim, material_laws(sc));
    } catch (const InputError& e) {
      s.fail("file", e.what());
    }
  }
  const bool per_particle_material = has_column(columns, ParticleColumn::Role::material);
  if (per_particle_material && s.has("material"))
    s.fail("material",
           "the particle file gives each particle's material (its column 'material'); drop material");
  // A mesh body's physical groups may each have a material; `material` is then that of the others.
  const bool mesh = b.shape == SceneBody::Shape::mesh;
  if (!mesh)
    for (const char* key : {"materials", "quadrature"})
      if (s.has(key)) s.fail(key, "for a mesh body (shape = \"mesh\") only");
  if (mesh && s.has("ppc"))
    s.fail("ppc", "a mesh body's particles are its elements' Gauss points (set their rule with quadrature)");
  const bool per_group_only = mesh && s.has("materials") && !s.has("material");
  const std::string material =  // with a material column or groups' materials, only a placeholder
      per_particle_material || per_group_only
          ? sc.materials[0].name
          : s.text("material", sc.materials.size() == 1 ? sc.materials[0].name : "");
  if (material.empty()) s.fail("material", "missing (the name of a [[materials]] entry)");
  auto found = std::find_if(sc.materials.begin(), sc.materials.end(),
                            [&](const SceneMaterial& m) { return m.name == material; });
  if (found == sc.materials.end()) {
    std::vector<std::string> names;
    for (const SceneMaterial& m : sc.materials) names.push_back(m.name);
    s.fail("material", "no material named " + in_quotes(material) + " (defined: " + join(names) + ")");
  }
  b.material = static_cast<std::size_t>(found - sc.materials.begin());
  if (mesh) {
    std::map<std::string, std::size_t> groups;
    if (const toml::table* t = s.table("materials"))
      for (const auto& [group, node] : *t) {
        const std::string name = node.value<std::string>().value_or("");
        const auto law = std::find_if(sc.materials.begin(), sc.materials.end(),
                                      [&](const SceneMaterial& m) { return m.name == name; });
        if (!node.is_string() || law == sc.materials.end())
          s.fail("materials", "physical group " + in_quotes(std::string(group.str())) +
                                  ": expected the name of a [[materials]] entry, got " + describe(node));
        groups[std::string(group.str())] = static_cast<std::size_t>(law - sc.materials.begin());
      }
    const int quadrature = s.integer("quadrature", 0);  // 0: by element type (read_mesh)
    if (s.has("quadrature") && (quadrature < 1 || quadrature > 8))
      s.fail("quadrature", "expected the degree of a Gauss rule, from 1 to 8");
    b.mesh_points = read_mesh(s, sc, b.file, quadrature, groups,
                              per_group_only ? std::nullopt : std::optional<std::size_t>(b.material));
  }
  if (s.has("velocity") && has_column(columns, ParticleColumn::Role::velocity))
    s.fail("velocity", "the particle file gives the velocities (its columns vx, ...); drop velocity");
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
    if (mesh)
      s.fail("k0",
             "a geostatic stress needs a body seeded on a lattice (it finds the top of each column of "
             "particles); a mesh body's Gauss points are not");
    if (per_particle_material || has_column(columns, ParticleColumn::Role::stress) ||
        has_column(columns, ParticleColumn::Role::plastic_strain))
      s.fail("k0", "the particle file gives the stresses or the materials; a geostatic stress needs neither");
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
  if (found->shape == SceneBody::Shape::mesh)
    t.fail("body",
           "surface loads need a body on a lattice (box, disk, sphere, ring, polygon, surface, or a particle "
           "file of equal cubes), not a mesh");
  if (found->shape == SceneBody::Shape::file && sc.geometry == Geometry::axisymmetric)
    t.fail(
        "body",
        "surface loads on a particle file's body are for plane and 3-D scenes: in axisymmetry a face's area "
        "per radian needs the lattice of a shape");
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
  read_shape(s, sc, "the rigid body", ShapeOwner::rigid_body, r);
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
  if (r.holds_inside && r.shape != SceneShape::Shape::box)
    s.fail("nodes", "nodes = \"inside\" holds the nodes in a box: for shape = \"box\" only");
  if (r.holds_inside && r.friction >= 0)
    s.fail(
        "nodes",
        "a Coulomb body's normals come from the nodes its points touch; drop nodes = \"inside\" or friction");
  sc.rigid_bodies.push_back(std::move(r));
}

}  // namespace mpm::scene_reading

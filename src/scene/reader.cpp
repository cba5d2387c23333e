// Reading scene files (TOML, through toml++): strict keys, typed values, physical validation.
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <system_error>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/scene/scene.hpp"
#include "section.hpp"

namespace mpm {

using namespace scene_reading;

namespace {
/// A constant's name must be a muParser identifier.
bool valid_name(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

/// Variables, pi, and the functions expressions may call.
bool reserved_name(const std::string& name) {
  static const std::set<std::string> reserved{
      "t",    "x",    "y",    "z",    "X",    "Y",     "Z",     "pi",    "sin",  "cos",   "tan", "asin",
      "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "log2", "log10", "log", "ln",
      "exp",  "sqrt", "sign", "rint", "abs",  "min",   "max",   "sum",   "avg",  "pow"};
  return reserved.count(name) > 0;
}

/// Apply one --set key.path=value to the document; returns the key path as error messages write it
/// ("bodies[0].radius" for bodies.0.radius).
std::string apply_override(toml::table& doc, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set: expected key.path=value, got " + in_quotes(assignment));
  const std::string path = assignment.substr(0, eq), value = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    parsed.insert_or_assign("v", value);  // a bare word: take it as a string
  }
  std::vector<std::string> keys;
  std::stringstream ss(path);
  for (std::string k; std::getline(ss, k, '.');) keys.push_back(k);
  if (keys.size() > max_key_depth)
    throw InputError("--set " + assignment.substr(0, 40) + "...: a key path deeper than " +
                     std::to_string(max_key_depth) + " levels");
  toml::node* at = &doc;
  std::string key_path;
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    const std::string& k = keys[i];
    if (toml::array* arr = at->as_array()) {
      std::size_t idx = 0;
      try {
        idx = std::stoul(k);
      } catch (const std::exception&) {
        throw InputError("--set " + path + ": '" + k + "' indexes an array and must be a number");
      }
      if (idx >= arr->size())
        throw InputError("--set " + path + ": index " + k + " is past the end of the array");
      at = arr->get(idx);
      key_path += "[" + k + "]";
    } else if (toml::table* tab = at->as_table()) {
      if (!tab->contains(k)) tab->insert(k, toml::table{});
      at = tab->get(k);
      key_path += (key_path.empty() ? "" : ".") + k;
    } else {
      throw InputError("--set " + path + ": '" + k + "' is not a table or array");
    }
  }
  toml::table* tab = at->as_table();
  if (!tab) throw InputError("--set " + path + ": the parent of '" + keys.back() + "' is not a table");
  tab->insert_or_assign(keys.back(), *parsed.get("v"));
  return key_path + (key_path.empty() ? "" : ".") + keys.back();
}

void read_simulation(const Section& s, Scene& sc) {
  sc.dim = s.integer("dimension", 2);
  if (sc.dim < 1 || sc.dim > 3) s.fail("dimension", "expected 1, 2 or 3");
  sc.end_time = s.required_number("end_time");
  if (!(sc.end_time > 0)) s.fail("end_time", "expected a positive time [s]");
  const std::string integrator = s.choice("integrator", "usl", {"usf", "usl", "cd", "musl", "implicit"});
  sc.implicit = integrator == "implicit";
  if (!sc.implicit) sc.integrator = parse_integrator(integrator);
  sc.kernel = parse_kernel(s.choice("kernel", "cpgimp", kernel_names()));
  if (s.has("gimp_length")) {
    sc.gimp_length = s.number("gimp_length", 0);
    if (!(*sc.gimp_length >= 0))
      s.fail("gimp_length", "expected a smoothing length >= 0 [m] (0: linear MPM)");
    if (sc.kernel != KernelKind::ugimp) s.fail("gimp_length", "applies to kernel = \"ugimp\" only");
  }
  if (s.has("dt") == s.has("cfl")) s.fail(s.has("dt") ? "dt" : "cfl", "give exactly one of dt [s] and cfl");
  sc.dt = s.number("dt", 0);
  sc.cfl = s.number("cfl", 0);
  if (s.has("dt") && !(sc.dt > 0)) s.fail("dt", "expected a positive time step [s]");
  if (s.has("dt") && sc.end_time / sc.dt > limits::max_steps)
    s.fail("dt", "end_time / dt = " + describe(*s.get("end_time")) + " / " + describe(*s.get("dt")) +
                     " is more than the 1e9 steps a run may take");
  if (s.has("cfl") && !(sc.cfl > 0 && sc.cfl <= 1)) s.fail("cfl", "expected a number in (0, 1]");
  sc.reproject_light_nodes = s.choice("light_nodes", "reproject", {"reproject", "none"}) == "reproject";
  sc.local_damping = s.number("local_damping", 0);
  if (!(sc.local_damping >= 0 && sc.local_damping < 1))
    s.fail("local_damping", "expected a number in [0, 1)");
  if (sc.local_damping > 0 && sc.implicit)
    s.fail("local_damping",
           "local damping is for the explicit integrators (the implicit one can take large steps)");
  // The particle velocity update: FLIP, blended with PIC by flip_fraction (1: FLIP alone), or APIC.
  sc.transfer = s.choice("transfer", "flip", {"flip", "apic"}) == "apic" ? Transfer::apic : Transfer::flip;
  sc.flip_fraction = s.number("flip_fraction", 1);
  if (!(sc.flip_fraction >= 0 && sc.flip_fraction <= 1))
    s.fail("flip_fraction", "expected a number in [0, 1]");
  if (sc.transfer == Transfer::apic && s.has("flip_fraction"))
    s.fail("flip_fraction", "applies to transfer = \"flip\" only (APIC's velocity is the grid's)");
  sc.threads = s.integer("threads", 0);
  if (sc.threads < 0 || sc.threads > max_threads)
    s.fail("threads", "expected 0 (all cores) or a positive count of at most " + std::to_string(max_threads));
  sc.geometry = parse_geometry(
      s.choice("geometry", "plane-strain", {"plane-strain", "plane-stress", "axisymmetric"}), "");
  if (s.has("geometry") && sc.dim != 2) s.fail("geometry", "applies to 2-D scenes only");
}

void read_grid(const Section& s, Scene& sc, const Locator& loc) {
  const auto n = static_cast<std::size_t>(sc.dim);
  sc.grid_lo = s.numbers("lo", n);
  sc.grid_hi = s.numbers("hi", n);
  const toml::array& cells = s.array("cells", n, "an array of " + std::to_string(n) + " positive integers");
  for (const toml::node& c : cells) {
    if (!c.is_integer() || c.value<std::int64_t>().value() < 1)
      s.fail("cells", "expected an array of " + std::to_string(n) + " positive integers, got " + describe(c) +
                          " in it");
    if (c.value<std::int64_t>().value() > limits::max_cells_per_axis)
      s.fail("cells", "expected at most " + std::to_string(limits::max_cells_per_axis) +
                          " cells per axis, got " + describe(c));
    sc.cells.push_back(static_cast<int>(c.value<std::int64_t>().value()));
  }
  for (std::size_t d = 0; d < n; ++d) {
    if (!(sc.grid_hi[d] > sc.grid_lo[d])) s.fail("hi", "expected hi > lo on every axis");
    const double h = (sc.grid_hi[d] - sc.grid_lo[d]) / sc.cells[d];
    if (d == 0) sc.h = h;
    if (std::abs(h - sc.h) > 1e-9 * sc.h)
      s.fail("cells", "cells must be square: (hi - lo)/cells is " + std::to_string(sc.h) + " on x but " +
                          std::to_string(h) + " on axis " + std::to_string(d));
  }
  const std::string accel = s.choice("constrained_acceleration", "zero", {"zero", "velocity-difference"});
  sc.constrained_acceleration =
      accel == "zero" ? ConstrainedAcceleration::zero : ConstrainedAcceleration::velocity_difference;
  sc.faces.assign(2 * n, SceneFace{});
  const toml::table* faces = s.table("faces");
  if (!faces) return;
  const std::vector<std::string> names(face_names.begin(), face_names.begin() + 2 * sc.dim);
  const Section f(*faces, s.key_of("faces"), loc, names);
  for (std::size_t k = 0; k < names.size(); ++k) {
    const toml::node* node = f.get(names[k]);
    if (!node) continue;
    SceneFace& face = sc.faces[k];
    if (node->is_string()) {
      const std::string kind =
          f.choice(names[k], "free", {"free", "fixed", "symmetry", "periodic", "outflow"});
      face.kind = kind == "free"       ? SceneFace::Kind::free
                  : kind == "fixed"    ? SceneFace::Kind::fixed
                  : kind == "symmetry" ? SceneFace::Kind::symmetry
                  : kind == "periodic" ? SceneFace::Kind::periodic
                                       : SceneFace::Kind::outflow;
    } else if (node->is_table()) {
      // { velocity = [...] }: a moving wall; { friction = mu }: a fixed Coulomb wall; both: a moving one;
      // { absorbing = "MATERIAL" }: dashpots for that material's waves.
      const Section v(*node->as_table(), f.key_of(names[k]), loc, {"velocity", "friction", "absorbing"});
      if (v.has("absorbing")) {
        if (v.has("velocity") || v.has("friction"))
          v.fail(v.has("velocity") ? "velocity" : "friction",
                 "an absorbing face takes no velocity or friction");
        if (sc.geometry == Geometry::axisymmetric)
          v.fail("absorbing", "absorbing faces are for plane and 3-D grids, not axisymmetric ones");
        face.kind = SceneFace::Kind::absorbing;
        face.absorbs = v.text("absorbing", "");
        continue;
      }
      if (!v.has("velocity") && !v.has("friction"))
        v.fail("velocity", "missing (an array of prescribed velocity components, or a friction coefficient)");
      face.kind = v.has("velocity") ? SceneFace::Kind::velocity : SceneFace::Kind::fixed;
      if (v.has("velocity")) face.velocity = v.expressions("velocity", n, time_var, sc.constants);
      if (v.has("friction")) {
        if (sc.implicit)
          v.fail("friction",
                 "Coulomb walls are for the explicit integrators; the implicit one holds every component "
                 "of a wall (write \"fixed\")");
        face.friction = v.constant_number("friction", 0.0, sc.constants);
        if (!(face.friction >= 0) || !std::isfinite(face.friction))
          v.fail("friction", "expected a friction coefficient >= 0, got " + std::to_string(face.friction));
      }
    } else {
      f.fail(names[k],
             "expected \"free\", \"fixed\", \"symmetry\", \"periodic\", \"outflow\", { velocity = [...] }, "
             "{ friction = mu } or { absorbing = \"MATERIAL\" }");
    }
  }
  for (std::size_t d = 0; d < n; ++d) {  // Steffen et al. 2008, Sec. 4.3: periodic faces come in pairs
    const bool lo = sc.faces[2 * d].kind == SceneFace::Kind::periodic,
               hi = sc.faces[2 * d + 1].kind == SceneFace::Kind::periodic;
    if (lo != hi)
      f.fail(names[lo ? 2 * d + 1 : 2 * d], "expected \"periodic\", as the opposite face " +
                                                names[lo ? 2 * d : 2 * d + 1] +
                                                " is (periodic faces come in pairs)");
  }
}

/// The impedances rho0 c_p and rho0 c_s of each absorbing face from the material it names (read after the
/// materials), with the small-strain moduli of that material.
void resolve_absorbing_faces(const Section& s, Scene& sc, const Locator& loc) {
  const std::vector<std::string> names(face_names.begin(), face_names.begin() + 2 * sc.dim);
  for (std::size_t k = 0; k < names.size(); ++k) {
    SceneFace& face = sc.faces[k];
    if (face.kind != SceneFace::Kind::absorbing) continue;
    const Section f(*s.table("faces"), s.key_of("faces"), loc, names);
    const Section v(*f.get(names[k])->as_table(), f.key_of(names[k]), loc, {"absorbing"});
    const auto m = std::find_if(sc.materials.begin(), sc.materials.end(),
                                [&](const SceneMaterial& x) { return x.name == face.absorbs; });
    if (m == sc.materials.end()) v.fail("absorbing", "no material named " + in_quotes(face.absorbs));
    const ElasticModuli e = small_strain_moduli(m->law);
    face.normal_impedance =
        std::sqrt((e.lambda + 2 * e.mu) * m->density);    // rho c_p, Lysmer & Kuhlemeyer 1969
    face.shear_impedance = std::sqrt(e.mu * m->density);  // rho c_s
    if (!(face.normal_impedance > 0))
      v.fail("absorbing", "material '" + face.absorbs + "' has no elastic stiffness to give a wave speed");
  }
}

void read_implicit(const Section& s, Scene& sc) {
  SceneImplicit& im = sc.implicit_step;
  im.theta = s.number("theta", 1);
  if (!(im.theta >= 0 && im.theta <= 1))
    s.fail("theta", "expected a number in [0, 1] (0 explicit, 1 fully implicit)");
  im.formulation = parse_formulation(s.choice("formulation", "momentum", {"velocity", "momentum"}), "");
  im.solver = parse_solver(
      s.choice("solver", "newton-gmres", {"newton-gmres", "newton-cg", "cg", "newton-direct"}), "");
  if ((im.solver == ImplicitSolver::newton_cg || im.solver == ImplicitSolver::linear_cg) &&
      im.formulation != Formulation::velocity)
    s.fail("solver", "CG needs the symmetric velocity formulation (formulation = \"velocity\")");
  numerics::NewtonSettings& n = im.newton;
  n.newton_tolerance = s.number("newton_tolerance", 1e-5);
  n.linear_tolerance = s.number("linear_tolerance", 1e-3);
  n.derivative_step = s.number("derivative_step", 1e-5);
  n.restart = s.integer("restart", 20);
  n.max_newton = s.integer("max_newton", 50);
  n.max_krylov = s.integer("max_krylov", 500);
  n.line_search = s.choice("line_search", "on", {"on", "off"}) == "on";
  n.max_backtracks = s.integer("max_backtracks", 10);
  n.forcing = s.choice("forcing", "constant", {"constant", "eisenstat-walker"}) == "constant"
                  ? numerics::Forcing::constant
                  : numerics::Forcing::eisenstat_walker;
  im.frozen_jacobian = s.choice("preconditioner", "none", {"none", "frozen-jacobian"}) == "frozen-jacobian";
  n.refresh_after = s.integer("refresh_after", 8);
  im.scaled_residual = s.choice("residual", "scaled", {"scaled", "unscaled"}) == "scaled";
  im.consistent_mass = s.choice("mass", "lumped", {"lumped", "consistent"}) == "consistent";
  if (im.consistent_mass && im.formulation != Formulation::velocity)
    s.fail("mass", "the consistent mass matrix needs the velocity formulation (formulation = \"velocity\")");
  if (im.consistent_mass && (im.frozen_jacobian || im.solver == ImplicitSolver::newton_direct))
    s.fail("mass",
           "the assembled Jacobians of preconditioner = \"frozen-jacobian\" and solver = \"newton-direct\" "
           "use the lumped mass");
  if (im.consistent_mass && sc.transfer == Transfer::apic)
    s.fail("mass", "APIC (simulation.transfer = \"apic\") runs with the lumped mass");
  im.move_with_projected_velocity =
      s.choice("positions", "momentum", {"momentum", "projected-velocity"}) == "projected-velocity";
  if (s.has("positions") && !im.move_with_projected_velocity && sc.kernel == KernelKind::cpdi2)
    s.fail("positions",
           "\"momentum\" moves CPDI2's corners by a field the stress never resists, and their domains "
           "fold; kernel = \"cpdi2\" moves them with \"projected-velocity\"");
  if (s.has("positions") && im.formulation != Formulation::momentum)
    s.fail("positions",
           "belongs to the momentum formulation (formulation = \"momentum\"); the velocity formulation "
           "moves the particles with its unknown");
  try {
    numerics::validate(n, "");
  } catch (const InputError& e) {  // "KEY: what": report it at the key as written in the file
    const std::string what = e.what();
    const std::size_t colon = what.find(": ");
    s.fail(what.substr(0, colon), what.substr(colon + 2));
  }
  im.step_factor = s.positive("step_factor", 1);
  im.start_factor = s.positive("start_factor", 1);
  im.growth = s.number("growth", 1.2);
  if (!(im.growth >= 1)) s.fail("growth", "expected a step growth factor >= 1");
  im.max_retries = s.integer("max_retries", 8);
  if (im.max_retries < 0) s.fail("max_retries", "expected a non-negative count");
  if (im.theta == 0 && im.step_factor > 1)
    s.fail("step_factor", "theta = 0 is explicit (stable up to the CFL step): expected step_factor <= 1");
}

}  // namespace

Scene read_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  std::ifstream is(file);
  std::error_code ec;  // a name the file system refuses (too long, say) is an error, not an exception
  if (!is || !std::filesystem::is_regular_file(file, ec))
    throw InputError(shortened(file.string()) + ": cannot open the scene file");
  std::stringstream ss;
  ss << is.rdbuf();
  return read_scene_text(ss.str(), file, overrides);
}

Scene read_scene_text(const std::string& text, const std::filesystem::path& file,
                      const std::vector<std::string>& overrides) {
  Scene sc;
  sc.file = file;
  sc.text = text;
  Locator loc{file.string(), {}};
  toml::table doc;
  refuse_deep_keys(sc.text, file.string());
  try {
    doc = toml::parse(sc.text, file.string());
  } catch (const toml::parse_error& e) {
    throw InputError(file.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                     std::string(e.description()));
  }
  for (const std::string& o : overrides) loc.overrides.emplace_back(apply_override(doc, o), o);
  sc.overrides = overrides;
  std::ostringstream resolved;
  resolved << doc << '\n';
  sc.resolved_text = resolved.str();

  const Section top(doc, "", loc,
                    {"simulation", "output", "constants", "grid", "materials", "bodies", "rigid_bodies",
                     "contact", "implicit", "loads", "check"});
  if (const toml::table* c = top.table("constants")) {
    for (auto&& [k, v] : *c) {
      const std::string name(k.str());
      if (!v.is_number()) loc.fail(&v, "constants." + name, "expected a number, got " + describe(v));
      if (!std::isfinite(number_value(v)))
        loc.fail(&v, "constants." + name, "expected a finite number, got " + describe(v));
      if (!valid_name(name))
        loc.fail(&v, "constants." + name,
                 "expected a name of letters, digits and '_' that starts with a letter");
      if (reserved_name(name))
        loc.fail(&v, "constants." + name, "'" + name + "' is reserved for a variable, pi or a function");
      sc.constants[name] = number_value(v);
    }
  }
  const std::vector<std::string> simulation_keys{
      "dimension", "end_time", "integrator",  "kernel",        "gimp_length", "dt",           "cfl",
      "threads",   "geometry", "light_nodes", "local_damping", "transfer",    "flip_fraction"};
  const toml::table* sim = top.table("simulation");
  if (!sim)
    top.fail("simulation", "missing [simulation] table (dimension, end_time, integrator, kernel, dt or cfl)");
  read_simulation(Section(*sim, "simulation", loc, simulation_keys), sc);
  const std::vector<std::string> output_keys = {"every", "newton_log"};
  if (const toml::table* out = top.table("output")) {
    const Section s(*out, "output", loc, output_keys);
    sc.output_every = s.number("every", 0);
    sc.newton_log = s.choice("newton_log", "off", {"off", "on"}) == "on";
    if (sc.newton_log && !sc.implicit)
      s.fail("newton_log",
             "newton.csv logs the Newton iterations of integrator = \"implicit\"; this run is explicit");
    if (sc.output_every < 0)
      s.fail("every", "expected a non-negative interval [s] (0: first and last state only)");
    if (sc.output_every > 0 && sc.end_time / sc.output_every > limits::max_frames)
      s.fail("every", "end_time / every = " + describe(toml::value<double>(sc.end_time / sc.output_every)) +
                          " frames; at most " + std::to_string(static_cast<long>(limits::max_frames)) +
                          " are written");
  }
  const toml::table* grid = top.table("grid");
  if (!grid) top.fail("grid", "missing [grid] table (lo, hi, cells, faces)");
  read_grid(Section(*grid, "grid", loc, {"lo", "hi", "cells", "faces", "constrained_acceleration"}), sc, loc);
  for (int d = 0; d < sc.dim; ++d)  // the two faces' stencils of a clamped B-spline must not overlap
    if (sc.faces[2 * d].kind != SceneFace::Kind::periodic && sc.cells[d] < clamped_cells_needed(sc.kernel))
      Section(*grid, "grid", loc, {"lo", "hi", "cells", "faces", "constrained_acceleration"})
          .fail("cells", "kernel = \"" + std::string(to_string(sc.kernel)) + "\" needs at least " +
                             std::to_string(clamped_cells_needed(sc.kernel)) +
                             " cells along every axis that is not periodic, got " +
                             std::to_string(sc.cells[d]) + " on axis " + std::to_string(d));
  if (sc.gimp_length > sc.h)  // Steffen et al. 2008, Sec. 4.1: the smoothing length lies in [0, h]
    Section(*sim, "simulation", loc, simulation_keys)
        .fail("gimp_length",
              "expected a smoothing length in [0, h] with h = " + std::to_string(sc.h) + " the cell size");
  if (sc.gimp_length == 0.0)
    sc.kernel = KernelKind::linear;  // Steffen et al. 2008, Sec. 4.1: l = 0 is linear MPM
  // Read and checked whatever the integrator, so that one scene runs implicitly or (--set) explicitly.
  if (const toml::table* im = top.table("implicit")) {
    read_implicit(Section(*im, "implicit", loc,
                          {"theta",
                           "formulation",
                           "solver",
                           "newton_tolerance",
                           "linear_tolerance",
                           "derivative_step",
                           "restart",
                           "max_newton",
                           "max_krylov",
                           "line_search",
                           "max_backtracks",
                           "forcing",
                           "preconditioner",
                           "refresh_after",
                           "residual",
                           "mass",
                           "positions",
                           "step_factor",
                           "start_factor",
                           "growth",
                           "max_retries"}),
                  sc);
  }
  const SceneImplicit& step = sc.implicit_step;
  if (sc.newton_log &&
      (step.solver == ImplicitSolver::linear_cg || (step.theta == 0 && !step.consistent_mass)))
    Section(*top.table("output"), "output", loc, output_keys)
        .fail("newton_log",
              "this implicit step takes no Newton iterations to log (solver = \"cg\" solves one linear "
              "system; theta = 0 is explicit)");
  const std::vector<const toml::table*> materials = top.tables("materials");
  if (materials.empty()) top.fail("materials", "missing: at least one [[materials]] table is needed");
  for (std::size_t k = 0; k < materials.size(); ++k)
    read_material(Section(*materials[k], "materials[" + std::to_string(k) + "]", loc, material_keys()), sc);
  resolve_absorbing_faces(
      Section(*grid, "grid", loc, {"lo", "hi", "cells", "faces", "constrained_acceleration"}), sc, loc);
  const std::vector<const toml::table*> bodies = top.tables("bodies");
  if (bodies.empty()) top.fail("bodies", "missing: at least one [[bodies]] table is needed");
  for (std::size_t k = 0; k < bodies.size(); ++k)
    read_body(Section(*bodies[k], "bodies[" + std::to_string(k) + "]", loc, {"name",
                                                                             "shape",
                                                                             "lo",
                                                                             "hi",
                                                                             "center",
                                                                             "radius",
                                                                             "inner_radius",
                                                                             "vertices",
                                                                             "file",
                                                                             "materials",
                                                                             "quadrature",
                                                                             "scale",
                                                                             "translate",
                                                                             "ppc",
                                                                             "add",
                                                                             "subtract",
                                                                             "intersect",
                                                                             "material",
                                                                             "velocity",
                                                                             "displacement",
                                                                             "deformation_gradient",
                                                                             "k0"}),
              sc, k);
  const std::vector<const toml::table*> rigid = top.tables("rigid_bodies");
  for (std::size_t k = 0; k < rigid.size(); ++k)
    read_rigid_body(
        Section(*rigid[k], "rigid_bodies[" + std::to_string(k) + "]", loc,
                {"name", "shape", "lo", "hi", "center", "radius", "inner_radius", "vertices", "file", "scale",
                 "translate", "ppc", "velocity", "contact_axes", "friction", "nodes"}),
        sc, k);
  const std::vector<const toml::table*> contacts = top.tables("contact");
  for (std::size_t k = 0; k < contacts.size(); ++k)
    read_contact(Section(*contacts[k], "contact[" + std::to_string(k) + "]", loc,
                         {"bodies", "friction", "normals", "gap"}),
                 sc);
  assign_fields(sc);
  if (const toml::table* loads = top.table("loads"))
    read_loads(Section(*loads, "loads", loc, {"gravity", "body_force", "traction", "pressure"}), sc, loc);
  else
    sc.gravity.assign(static_cast<std::size_t>(sc.dim), 0.0);
  for (const SceneBody& b : sc.bodies)
    if (!b.displacement.empty() && is_rate_form(sc.materials[b.material].law))
      top.fail("bodies",
               "body '" + b.name + "': a rate-form material starts undeformed (no initial displacement)");
  if (const toml::table* check = top.table("check")) {
    const Section s(*check, "check", loc, {"displacement"});
    if (!s.has("displacement"))
      s.fail("displacement", "missing (the exact displacement, expressions of X, Y, Z, t)");
    sc.exact_displacement = s.expressions("displacement", static_cast<std::size_t>(sc.dim),
                                          reference_time_vars[sc.dim - 1], sc.constants);
  }
  return sc;
}

}  // namespace mpm

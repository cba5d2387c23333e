// Reading scene files (TOML, through toml++): strict keys, typed values, physical validation.
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {

namespace {

/// Where a value came from, for error messages: "FILE:LINE: key.path", or "FILE: key.path (from --set ...)" for
/// a value given on the command line.
struct Locator {
  std::string file;
  std::vector<std::pair<std::string, std::string>> overrides;  ///< key path set by --set, and the assignment

  std::string where(const toml::node* node, const std::string& key) const {
    if (node && node->source().begin.line > 0)
      return file + ":" + std::to_string(node->source().begin.line) + ": " + key;
    auto under = [](const std::string& a, const std::string& b) {  // a is b or lies inside it
      return a.size() > b.size() ? a.compare(0, b.size(), b) == 0 && (a[b.size()] == '.' || a[b.size()] == '[')
                                 : a == b;
    };
    for (const auto& [set_key, assignment] : overrides)
      if (under(key, set_key) || under(set_key, key)) return file + ": " + key + " (from --set " + assignment + ")";
    return file + ": " + key;
  }
  [[noreturn]] void fail(const toml::node* node, const std::string& key, const std::string& what) const {
    throw InputError(where(node, key) + ": " + what);
  }
};

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string describe(const toml::node& n) {
  std::ostringstream os;
  if (n.is_string())
    os << '\'' << n.value<std::string>().value_or("") << '\'';
  else if (n.is_table())
    os << "a table";
  else if (n.is_array())
    os << "an array of " << n.as_array()->size();
  else
    n.visit([&](auto&& v) { os << v; });
  return os.str();
}

/// Reads one TOML table; remembers which keys were used so that unknown keys (typos) are errors.
class Section {
 public:
  Section(const toml::table& t, std::string path, const Locator& loc, std::vector<std::string> allowed)
      : t_(t), path_(std::move(path)), loc_(loc), allowed_(std::move(allowed)) {
    for (auto&& [k, v] : t_) {
      const std::string key(k.str());
      if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end())
        loc_.fail(&v, key_of(key), std::string(v.is_table() ? "unknown table" : "unknown key") + " (expected one of " +
                                       join(allowed_) + ")");
    }
  }

  std::string key_of(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  const toml::node* get(const std::string& k) const { return t_.get(k); }
  bool has(const std::string& k) const { return t_.contains(k); }
  [[noreturn]] void fail(const std::string& k, const std::string& what) const {
    const toml::node* n = get(k);
    loc_.fail(n ? n : (path_.empty() ? nullptr : &t_), key_of(k), what);  // the document's line 1 would mislead
  }

  double number(const std::string& k, double fallback) const {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_number()) fail(k, "expected a number, got " + describe(*n));
    if (!std::isfinite(n->value<double>().value())) fail(k, "expected a finite number, got " + describe(*n));
    return n->value<double>().value();
  }
  double required_number(const std::string& k) const {
    if (!has(k)) fail(k, "missing (a number is required)");
    return number(k, 0);
  }
  double positive(const std::string& k, double fallback) const {
    const double v = number(k, fallback);
    if (!(v > 0) && has(k)) fail(k, "expected a positive number, got " + describe(*get(k)));
    return v;
  }
  int integer(const std::string& k, int fallback) const {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_integer()) fail(k, "expected an integer, got " + describe(*n));
    const std::int64_t v = n->value<std::int64_t>().value();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      fail(k, "expected an integer, got " + describe(*n) + " (out of range)");
    return static_cast<int>(v);
  }
  std::string text(const std::string& k, const std::string& fallback) const {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_string()) fail(k, "expected a string, got " + describe(*n));
    return n->value<std::string>().value();
  }
  std::string choice(const std::string& k, const std::string& fallback, const std::vector<std::string>& options) const {
    const std::string v = text(k, fallback);
    if (std::find(options.begin(), options.end(), v) == options.end())
      fail(k, "expected one of " + join(options) + ", got '" + v + "'");
    return v;
  }
  const toml::array& array(const std::string& k, std::size_t n, const std::string& what) const {
    const toml::node* node = get(k);
    if (!node || !node->is_array() || (n > 0 && node->as_array()->size() != n))
      fail(k, "expected " + what + (node ? ", got " + describe(*node) : ""));
    return *node->as_array();
  }
  std::vector<double> numbers(const std::string& k, std::size_t n) const {
    const toml::array& a = array(k, n, "an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const toml::node& e : a) {
      if (!e.is_number() || !std::isfinite(e.value<double>().value()))
        fail(k, "expected an array of " + std::to_string(n) + " finite numbers, got " + describe(e) + " in it");
      out.push_back(e.value<double>().value());
    }
    return out;
  }
  /// An array of n components, each a number or an expression string over `vars`.
  std::vector<ExpressionPtr> expressions(const std::string& k, std::size_t n, const std::vector<std::string>& vars,
                                         const std::map<std::string, double>& constants) const {
    const std::string what = "an array of " + std::to_string(n) + " numbers or expression strings of " +
                             (vars.empty() ? std::string("nothing") : join(vars));
    const toml::array& a = array(k, n, what);
    std::vector<ExpressionPtr> out;
    for (std::size_t c = 0; c < a.size(); ++c) {
      const toml::node& e = *a.get(c);
      std::string src;
      if (e.is_number()) {
        std::ostringstream os;
        os.precision(17);
        os << e.value<double>().value();
        src = os.str();
      } else if (e.is_string()) {
        src = e.value<std::string>().value();
      } else {
        fail(k, "expected " + what + ", got " + describe(e) + " in it");
      }
      out.push_back(std::make_shared<Expression>(src, vars, constants, loc_.where(&e, key_of(k) + "[" + std::to_string(c) + "]")));
    }
    return out;
  }
  const toml::table* table(const std::string& k) const {
    const toml::node* n = get(k);
    if (!n) return nullptr;
    if (!n->is_table()) fail(k, "expected a table, got " + describe(*n));
    return n->as_table();
  }
  /// An array of tables ([[k]]).
  std::vector<const toml::table*> tables(const std::string& k) const {
    std::vector<const toml::table*> out;
    const toml::node* n = get(k);
    if (!n) return out;
    if (!n->is_array_of_tables()) fail(k, "expected one or more [[" + key_of(k) + "]] tables");
    for (const toml::node& e : *n->as_array()) out.push_back(e.as_table());
    return out;
  }

 private:
  const toml::table& t_;
  std::string path_;
  const Locator& loc_;
  std::vector<std::string> allowed_;
};

/// A constant's name must be a muParser identifier.
bool valid_name(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

/// Variables, pi, and the functions expressions may call.
bool reserved_name(const std::string& name) {
  static const std::set<std::string> reserved{
      "t",    "x",     "y",     "z",    "X",    "Y",    "Z",     "pi",    "sin",  "cos",  "tan", "asin", "acos",
      "atan", "sinh",  "cosh",  "tanh", "asinh", "acosh", "atanh", "log2", "log10", "log", "ln",  "exp",  "sqrt",
      "sign", "rint",  "abs",   "min",  "max",  "sum",  "avg",   "pow"};
  return reserved.count(name) > 0;
}

const std::vector<std::string> position_vars[] = {{"x"}, {"x", "y"}, {"x", "y", "z"}};
const std::vector<std::string> reference_vars[] = {{"X"}, {"X", "Y"}, {"X", "Y", "Z"}};
const std::vector<std::string> reference_time_vars[] = {{"X", "t"}, {"X", "Y", "t"}, {"X", "Y", "Z", "t"}};
const std::vector<std::string> time_var{"t"};

/// Apply one --set key.path=value to the document; returns the key path as error messages write it
/// ("bodies[0].radius" for bodies.0.radius).
std::string apply_override(toml::table& doc, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set: expected key.path=value, got '" + assignment + "'");
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
      if (idx >= arr->size()) throw InputError("--set " + path + ": index " + k + " is past the end of the array");
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
  sc.kernel = parse_kernel(s.choice("kernel", "cpgimp", {"linear", "ugimp", "cpgimp", "bspline2", "bspline3"}));
  sc.gimp_length = s.number("gimp_length", 0);
  if (sc.gimp_length < 0) s.fail("gimp_length", "expected a non-negative length [m]");
  if (sc.gimp_length > 0 && sc.kernel != KernelKind::ugimp) s.fail("gimp_length", "applies to kernel = \"ugimp\" only");
  if (s.has("dt") == s.has("cfl")) s.fail(s.has("dt") ? "dt" : "cfl", "give exactly one of dt [s] and cfl");
  sc.dt = s.number("dt", 0);
  sc.cfl = s.number("cfl", 0);
  if (s.has("dt") && !(sc.dt > 0)) s.fail("dt", "expected a positive time step [s]");
  if (s.has("dt") && sc.end_time / sc.dt > limits::max_steps)
    s.fail("dt", "end_time / dt = " + describe(*s.get("end_time")) + " / " + describe(*s.get("dt")) +
                     " is more than the 1e9 steps a run may take");
  if (s.has("cfl") && !(sc.cfl > 0 && sc.cfl <= 1)) s.fail("cfl", "expected a number in (0, 1]");
  sc.reproject_light_nodes = s.choice("light_nodes", "reproject", {"reproject", "none"}) == "reproject";
  sc.threads = s.integer("threads", 0);
  if (sc.threads < 0) s.fail("threads", "expected 0 (all cores) or a positive count");
  sc.geometry = parse_geometry(s.choice("geometry", "plane-strain", {"plane-strain", "plane-stress", "axisymmetric"}), "");
  if (s.has("geometry") && sc.dim != 2) s.fail("geometry", "applies to 2-D scenes only");
}

void read_grid(const Section& s, Scene& sc, const Locator& loc) {
  const auto n = static_cast<std::size_t>(sc.dim);
  sc.grid_lo = s.numbers("lo", n);
  sc.grid_hi = s.numbers("hi", n);
  const toml::array& cells = s.array("cells", n, "an array of " + std::to_string(n) + " positive integers");
  for (const toml::node& c : cells) {
    if (!c.is_integer() || c.value<std::int64_t>().value() < 1)
      s.fail("cells", "expected an array of " + std::to_string(n) + " positive integers, got " + describe(c) + " in it");
    if (c.value<std::int64_t>().value() > limits::max_cells_per_axis)
      s.fail("cells", "expected at most " + std::to_string(limits::max_cells_per_axis) + " cells per axis, got " +
                          describe(c));
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
  const std::string accel =
      s.choice("constrained_acceleration", "zero", {"zero", "velocity-difference"});
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
      const std::string kind = f.choice(names[k], "free", {"free", "fixed", "symmetry"});
      face.kind = kind == "free" ? SceneFace::Kind::free
                                 : (kind == "fixed" ? SceneFace::Kind::fixed : SceneFace::Kind::symmetry);
    } else if (node->is_table()) {
      const Section v(*node->as_table(), f.key_of(names[k]), loc, {"velocity"});
      if (!v.has("velocity")) v.fail("velocity", "missing (an array of prescribed velocity components)");
      face.kind = SceneFace::Kind::velocity;
      face.velocity = v.expressions("velocity", n, time_var, sc.constants);
    } else {
      f.fail(names[k], "expected \"free\", \"fixed\", \"symmetry\" or { velocity = [...] }");
    }
  }
}

/// The rate-form laws of Sulsky & Kaul 2004: hypoelastic, or von Mises with the bilinear hardening law.
ElastoPlastic read_rate_form(const Section& s, const std::string& model, double rho) {
  for (const char* k : {"lambda", "mu"})
    if (s.has(k)) s.fail(k, "give E and nu for the " + model + " model");
  const double E = s.required_number("E"), nu = s.required_number("nu");
  if (!(E > 0)) s.fail("E", "expected a positive Young's modulus [Pa]");
  if (!(nu > -1 && nu < 0.5)) s.fail("nu", "expected a Poisson ratio in (-1, 0.5)");
  ElastoPlastic law;
  law.E = E;
  law.nu = nu;
  law.rho0 = rho;
  law.specific_heat = s.number("specific_heat", 0);
  if (law.specific_heat < 0) s.fail("specific_heat", "expected a non-negative specific heat [J/(kg K)]");
  law.plastic = model == "von-mises";
  if (law.plastic) {
    law.law.yield = s.required_number("yield_strength");
    law.law.hardening = s.number("hardening", 0);
    law.law.limit = s.number("limit_strength", std::numeric_limits<double>::infinity());
    law.law.softening = s.number("softening", 0);
    law.law.residual = s.number("residual_strength", 0);
    try {
      validate(law.law, "law");
    } catch (const InputError& e) {  // "law.KEY: what": report it at the key as written in the file
      const std::string what = e.what();
      const std::size_t dot = what.find('.'), colon = what.find(": ");
      s.fail(what.substr(dot + 1, colon - dot - 1), what.substr(colon + 2));
    }
  } else {
    for (const char* k : {"yield_strength", "hardening", "limit_strength", "softening", "residual_strength"})
      if (s.has(k)) s.fail(k, "applies to model = \"von-mises\" only");
  }
  return law;
}

/// The Newtonian fluid of Sulsky & Kaul 2004, Eq. (2.1.7).
NewtonianFluid read_fluid(const Section& s, const Scene& sc, double rho) {
  if (sc.geometry != Geometry::plane_strain)
    s.fail("model", "a Newtonian fluid runs in plane strain; plane stress and axisymmetry need model = "
                    "\"hypoelastic\" or \"von-mises\"");
  NewtonianFluid f;
  f.rho0 = rho;
  f.mu = s.required_number("viscosity");
  if (!(f.mu >= 0)) s.fail("viscosity", "expected a shear viscosity >= 0 [Pa s]");
  f.lambda = s.number("second_viscosity", -2 * f.mu / 3);
  if (!(3 * f.lambda + 2 * f.mu >= 0)) s.fail("second_viscosity", "expected lambda >= -2 mu / 3 [Pa s]");
  f.bulk = s.number("bulk_modulus", 0);
  if (!(f.bulk >= 0)) s.fail("bulk_modulus", "expected a bulk modulus >= 0 [Pa]");
  if (!(f.bulk > 0 || f.mu > 0)) s.fail("viscosity", "a fluid needs a viscosity or a bulk modulus > 0");
  return f;
}

/// The Neo-Hookean law from E and nu, or lambda and mu.
NeoHookean read_neo_hookean(const Section& s, const Scene& sc, double rho) {
  if (sc.geometry != Geometry::plane_strain)
    s.fail("model", "a Neo-Hookean material runs in plane strain; plane stress and axisymmetry need model = "
                    "\"hypoelastic\" or \"von-mises\"");
  const bool young = s.has("E") || s.has("nu"), lame = s.has("lambda") || s.has("mu");
  if (young == lame) s.fail(young ? "lambda" : "E", "give either E and nu, or lambda and mu");
  if (young) {
    const double E = s.required_number("E"), nu = s.required_number("nu");
    if (!(E > 0)) s.fail("E", "expected a positive Young's modulus [Pa]");
    if (!(nu > -1 && nu < 0.5)) s.fail("nu", "expected a Poisson ratio in (-1, 0.5)");
    return NeoHookean::from_young_poisson(E, nu, rho);
  }
  const double lambda = s.required_number("lambda"), mu = s.required_number("mu");
  if (!(mu > 0)) s.fail("mu", "expected a positive shear modulus [Pa]");
  if (!(lambda + 2 * mu / 3 > 0)) s.fail("lambda", "expected lambda + 2 mu / 3 > 0 (positive bulk modulus)");
  return NeoHookean{lambda, mu, rho};
}

void read_material(const Section& s, Scene& sc) {
  SceneMaterial m;
  m.name = s.text("name", "");
  if (m.name.empty()) s.fail("name", "missing (each material needs a name bodies refer to)");
  for (const SceneMaterial& other : sc.materials)
    if (other.name == m.name) s.fail("name", "material '" + m.name + "' is defined twice");
  const std::string model =
      s.choice("model", "neo-hookean", {"neo-hookean", "hypoelastic", "von-mises", "newtonian-fluid"});
  const double rho = s.required_number("density");
  if (!(rho > 0)) s.fail("density", "expected a positive density [kg/m^3]");
  m.density = rho;
  if (model == "neo-hookean")
    m.law = read_neo_hookean(s, sc, rho);
  else if (model == "newtonian-fluid")
    m.law = read_fluid(s, sc, rho);
  else
    m.law = read_rate_form(s, model, rho);
  sc.materials.push_back(m);
}

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

void read_body(const Section& s, Scene& sc, std::size_t index) {
  const auto n = static_cast<std::size_t>(sc.dim);
  SceneBody b;
  b.name = s.text("name", "body " + std::to_string(index));
  const std::string shape = s.choice("shape", "box", {"box", "disk", "sphere", "ring", "file"});
  if (shape == "box") {
    b.shape = SceneBody::Shape::box;
    b.lo = s.numbers("lo", n);
    b.hi = s.numbers("hi", n);
    for (std::size_t d = 0; d < n; ++d)
      if (!(b.hi[d] > b.lo[d])) s.fail("hi", "expected hi > lo on every axis");
    const std::string side = outside_grid(sc, b.lo, b.hi);
    if (!side.empty()) s.fail(side, "the box must lie inside the grid " + grid_extent(sc));
  } else if (shape == "file") {
    b.shape = SceneBody::Shape::file;
    b.file = s.text("file", "");
    if (b.file.empty()) s.fail("file", "missing (a CSV file of positions and volumes)");
    if (b.file.is_relative()) b.file = sc.file.parent_path() / b.file;
    if (!std::filesystem::exists(b.file)) s.fail("file", "cannot open " + b.file.string());
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
    s.fail("material", "no material named '" + material + "' (defined: " + join(names) + ")");
  }
  b.material = static_cast<std::size_t>(found - sc.materials.begin());
  if (s.has("velocity")) b.velocity = s.expressions("velocity", n, position_vars[n - 1], sc.constants);
  if (s.has("displacement"))
    b.displacement = s.expressions("displacement", n, reference_vars[n - 1], sc.constants);
  if (s.has("deformation_gradient")) {
    if (!s.has("displacement")) s.fail("deformation_gradient", "needs the matching initial displacement");
    b.deformation = s.expressions("deformation_gradient", n * n, reference_vars[n - 1], sc.constants);
  }
  sc.bodies.push_back(std::move(b));
}

void read_loads(const Section& s, Scene& sc, const Locator& loc) {
  const auto n = static_cast<std::size_t>(sc.dim);
  sc.gravity = s.has("gravity") ? s.numbers("gravity", n) : std::vector<double>(n, 0.0);
  if (s.has("body_force")) sc.body_force = s.expressions("body_force", n, reference_time_vars[n - 1], sc.constants);
  const std::vector<const toml::table*> tractions = s.tables("traction");
  for (std::size_t k = 0; k < tractions.size(); ++k) {
    const Section t(*tractions[k], s.key_of("traction[" + std::to_string(k) + "]"), loc, {"body", "face", "traction"});
    SceneTraction tr;
    if (!t.has("body")) t.fail("body", "missing (the name of the loaded box body)");
    const std::string body = t.text("body", "");
    auto found = std::find_if(sc.bodies.begin(), sc.bodies.end(), [&](const SceneBody& b) { return b.name == body; });
    if (found == sc.bodies.end()) t.fail("body", "no body named '" + body + "'");
    if (found->shape != SceneBody::Shape::box) t.fail("body", "tractions apply to box bodies only");
    tr.body = static_cast<std::size_t>(found - sc.bodies.begin());
    const std::vector<std::string> names(face_names.begin(), face_names.begin() + 2 * sc.dim);
    const std::string face = t.choice("face", "", names);
    tr.face = static_cast<int>(std::find(names.begin(), names.end(), face) - names.begin());
    tr.traction = t.expressions("traction", n, time_var, sc.constants);
    sc.tractions.push_back(std::move(tr));
  }
}

void read_implicit(const Section& s, Scene& sc) {
  SceneImplicit& im = sc.implicit_step;
  im.theta = s.number("theta", 1);
  if (!(im.theta >= 0 && im.theta <= 1)) s.fail("theta", "expected a number in [0, 1] (0 explicit, 1 fully implicit)");
  im.formulation = parse_formulation(s.choice("formulation", "momentum", {"velocity", "momentum"}), "");
  im.solver = parse_solver(s.choice("solver", "newton-gmres", {"newton-gmres", "newton-cg", "cg"}), "");
  if (im.solver != ImplicitSolver::newton_gmres && im.formulation != Formulation::velocity)
    s.fail("solver", "CG needs the symmetric velocity formulation (formulation = \"velocity\")");
  implicit::NewtonSettings& n = im.newton;
  n.newton_tolerance = s.number("newton_tolerance", 1e-5);
  n.linear_tolerance = s.number("linear_tolerance", 1e-3);
  n.derivative_step = s.number("derivative_step", 1e-5);
  n.restart = s.integer("restart", 20);
  n.max_newton = s.integer("max_newton", 50);
  n.max_krylov = s.integer("max_krylov", 500);
  n.line_search = s.choice("line_search", "on", {"on", "off"}) == "on";
  n.max_backtracks = s.integer("max_backtracks", 10);
  n.forcing = s.choice("forcing", "constant", {"constant", "eisenstat-walker"}) == "constant"
                  ? implicit::Forcing::constant
                  : implicit::Forcing::eisenstat_walker;
  im.frozen_jacobian = s.choice("preconditioner", "none", {"none", "frozen-jacobian"}) == "frozen-jacobian";
  n.refresh_after = s.integer("refresh_after", 8);
  try {
    implicit::validate(n, "");
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

void read_rigid_body(const Section& s, Scene& sc, std::size_t index) {
  const auto n = static_cast<std::size_t>(sc.dim);
  SceneRigidBody r;
  r.name = s.text("name", "rigid " + std::to_string(index));
  s.choice("shape", "box", {"box"});
  r.lo = s.numbers("lo", n);
  r.hi = s.numbers("hi", n);
  for (std::size_t d = 0; d < n; ++d)
    if (!(r.hi[d] > r.lo[d])) s.fail("hi", "expected hi > lo on every axis");
  const std::string side = outside_grid(sc, r.lo, r.hi);
  if (!side.empty()) s.fail(side, "the rigid body must lie inside the grid " + grid_extent(sc));
  r.ppc = s.integer("ppc", 2);
  if (r.ppc < 1 || r.ppc > limits::max_ppc)
    s.fail("ppc", "expected at least 1 and at most " + std::to_string(limits::max_ppc) +
                     " points per cell per axis");
  if (!s.has("velocity")) s.fail("velocity", "missing (the prescribed velocity, numbers or expressions of t)");
  r.velocity = s.expressions("velocity", n, time_var, sc.constants);
  r.imposes.assign(n, !s.has("contact_axes"));
  if (s.has("contact_axes")) {
    static const std::vector<std::string> axes{"x", "y", "z"};
    const toml::array& a = s.array("contact_axes", 0, "an array of axis names (\"x\", \"y\", \"z\")");
    for (const toml::node& e : a) {
      const auto axis = std::find(axes.begin(), axes.begin() + sc.dim, e.value<std::string>().value_or(""));
      if (axis == axes.begin() + sc.dim) s.fail("contact_axes", "expected axis names of this dimension, got " + describe(e));
      r.imposes[static_cast<std::size_t>(axis - axes.begin())] = true;
    }
  }
  sc.rigid_bodies.push_back(std::move(r));
}

}  // namespace

Scene read_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  Scene sc;
  sc.file = file;
  Locator loc{file.string(), {}};
  {
    std::ifstream is(file);
    if (!is || !std::filesystem::is_regular_file(file)) throw InputError(file.string() + ": cannot open the scene file");
    std::stringstream ss;
    ss << is.rdbuf();
    sc.text = ss.str();
  }
  toml::table doc;
  try {
    doc = toml::parse(sc.text, file.string());
  } catch (const toml::parse_error& e) {
    throw InputError(file.string() + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  }
  for (const std::string& o : overrides) loc.overrides.emplace_back(apply_override(doc, o), o);

  const Section top(doc, "", loc, {"simulation", "output", "constants", "grid", "materials", "bodies", "rigid_bodies", "implicit", "loads", "check"});
  if (const toml::table* c = top.table("constants")) {
    for (auto&& [k, v] : *c) {
      const std::string name(k.str());
      if (!v.is_number()) loc.fail(&v, "constants." + name, "expected a number, got " + describe(v));
      if (!valid_name(name))
        loc.fail(&v, "constants." + name, "expected a name of letters, digits and '_' that starts with a letter");
      if (reserved_name(name))
        loc.fail(&v, "constants." + name, "'" + name + "' is reserved for a variable, pi or a function");
      sc.constants[name] = v.value<double>().value();
    }
  }
  const std::vector<std::string> simulation_keys{"dimension", "end_time", "integrator", "kernel", "gimp_length",
                                                 "dt", "cfl", "threads", "geometry", "light_nodes"};
  const toml::table* sim = top.table("simulation");
  if (!sim) top.fail("simulation", "missing [simulation] table (dimension, end_time, integrator, kernel, dt or cfl)");
  read_simulation(Section(*sim, "simulation", loc,
                          simulation_keys),
                  sc);
  if (const toml::table* out = top.table("output")) {
    const Section s(*out, "output", loc, {"every"});
    sc.output_every = s.number("every", 0);
    if (sc.output_every < 0) s.fail("every", "expected a non-negative interval [s] (0: first and last state only)");
    if (sc.output_every > 0 && sc.end_time / sc.output_every > limits::max_frames)
      s.fail("every", "end_time / every = " + describe(toml::value<double>(sc.end_time / sc.output_every)) +
                          " frames; at most " + std::to_string(static_cast<long>(limits::max_frames)) +
                          " are written");
  }
  const toml::table* grid = top.table("grid");
  if (!grid) top.fail("grid", "missing [grid] table (lo, hi, cells, faces)");
  read_grid(Section(*grid, "grid", loc, {"lo", "hi", "cells", "faces", "constrained_acceleration"}), sc, loc);
  if (sc.gimp_length > sc.h)  // Steffen et al. 2008, Sec. 4.1: the smoothing length lies in (0, h]
    Section(*sim, "simulation", loc, simulation_keys)
        .fail("gimp_length", "expected a smoothing length in (0, h] with h = " + std::to_string(sc.h) + " the cell size");
  // Read and checked whatever the integrator, so that one scene runs implicitly or (--set) explicitly.
  if (const toml::table* im = top.table("implicit")) {
    read_implicit(Section(*im, "implicit", loc,
                          {"theta", "formulation", "solver", "newton_tolerance", "linear_tolerance", "derivative_step",
                           "restart", "max_newton", "max_krylov", "line_search", "max_backtracks", "forcing",
                           "preconditioner", "refresh_after", "step_factor", "start_factor", "growth", "max_retries"}),
                  sc);
  }
  const std::vector<const toml::table*> materials = top.tables("materials");
  if (materials.empty()) top.fail("materials", "missing: at least one [[materials]] table is needed");
  for (std::size_t k = 0; k < materials.size(); ++k)
    read_material(Section(*materials[k], "materials[" + std::to_string(k) + "]", loc,
                          {"name", "model", "E", "nu", "lambda", "mu", "density", "specific_heat", "yield_strength",
                           "hardening", "limit_strength", "softening", "residual_strength", "viscosity", "second_viscosity",
                           "bulk_modulus"}),
                  sc);
  const std::vector<const toml::table*> bodies = top.tables("bodies");
  if (bodies.empty()) top.fail("bodies", "missing: at least one [[bodies]] table is needed");
  for (std::size_t k = 0; k < bodies.size(); ++k)
    read_body(Section(*bodies[k], "bodies[" + std::to_string(k) + "]", loc,
                      {"name", "shape", "lo", "hi", "center", "radius", "inner_radius", "file", "ppc", "material",
                       "velocity", "displacement", "deformation_gradient"}),
              sc, k);
  const std::vector<const toml::table*> rigid = top.tables("rigid_bodies");
  for (std::size_t k = 0; k < rigid.size(); ++k)
    read_rigid_body(Section(*rigid[k], "rigid_bodies[" + std::to_string(k) + "]", loc,
                            {"name", "shape", "lo", "hi", "ppc", "velocity", "contact_axes"}),
                    sc, k);
  if (const toml::table* loads = top.table("loads"))
    read_loads(Section(*loads, "loads", loc, {"gravity", "body_force", "traction"}), sc, loc);
  else
    sc.gravity.assign(static_cast<std::size_t>(sc.dim), 0.0);
  for (const SceneBody& b : sc.bodies)
    if (!b.displacement.empty() && is_rate_form(sc.materials[b.material].law))
      top.fail("bodies", "body '" + b.name + "': a rate-form material starts undeformed (no initial displacement)");
  if (const toml::table* check = top.table("check")) {
    const Section s(*check, "check", loc, {"displacement"});
    if (!s.has("displacement")) s.fail("displacement", "missing (the exact displacement, expressions of X, Y, Z, t)");
    sc.exact_displacement = s.expressions("displacement", static_cast<std::size_t>(sc.dim),
                                          reference_time_vars[sc.dim - 1], sc.constants);
  }
  return sc;
}

}  // namespace mpm

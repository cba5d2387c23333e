#pragma once
// The pieces of the scene reader shared by its files: where a value came from (Locator), a TOML table read
// with strict keys and typed values (Section), the variables expressions may use, and the readers of the
// tables (src/scene_reader.cpp: the file and [simulation], [grid], [implicit]; src/scene_read_materials.cpp;
// src/scene_read_bodies.cpp: bodies, rigid bodies, loads).
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm::scene_reading {

/// Where a value came from, for error messages: "FILE:LINE: key.path", or "FILE: key.path (from --set ...)"
/// for a value given on the command line.
struct Locator {
  std::string file;
  std::vector<std::pair<std::string, std::string>> overrides;  ///< key path set by --set, and the assignment

  std::string where(const toml::node* node, const std::string& key) const {
    if (node && node->source().begin.line > 0)
      return file + ":" + std::to_string(node->source().begin.line) + ": " + shortened(key);
    auto under = [](const std::string& a, const std::string& b) {  // a is b or lies inside it
      return a.size() > b.size()
                 ? a.compare(0, b.size(), b) == 0 && (a[b.size()] == '.' || a[b.size()] == '[')
                 : a == b;
    };
    for (const auto& [set_key, assignment] : overrides)
      if (under(key, set_key) || under(set_key, key))
        return file + ": " + shortened(key) + " (from --set " + shortened(assignment) + ")";
    return file + ": " + shortened(key);
  }
  [[noreturn]] void fail(const toml::node* node, const std::string& key, const std::string& what) const {
    throw InputError(where(node, key) + ": " + what);
  }
};

/// Names for a message, comma-separated, each cut to 80 characters (shortened).
inline std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + shortened(n);
  return s;
}

inline std::string describe(const toml::node& n) {
  std::ostringstream os;
  if (n.is_string())
    os << in_quotes(n.value<std::string>().value_or(""));
  else if (n.is_table())
    os << "a table";
  else if (n.is_array())
    os << "an array of " << n.as_array()->size();
  else
    n.visit([&](auto&& v) { os << v; });
  return os.str();
}

/// Reads one TOML table; remembers which keys were used so that unknown keys (typos) are errors.
/// The value of a number node, integer or floating point. An integer beyond 2^53 rounds to the nearest double
/// (toml++'s value<double>() gives none for it).
inline double number_value(const toml::node& n) {
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  return n.as_floating_point()->get();
}

class Section {
 public:
  Section(const toml::table& t, std::string path, const Locator& loc, std::vector<std::string> allowed)
      : t_(t), path_(std::move(path)), loc_(loc), allowed_(std::move(allowed)) {
    for (auto&& [k, v] : t_) {
      const std::string key(k.str());
      if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end())
        loc_.fail(&v, key_of(key),
                  std::string(v.is_table() ? "unknown table" : "unknown key") + " (expected one of " +
                      join(allowed_) + ")");
    }
  }

  std::string key_of(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  /// The section of table `t` at key path `path` below this one, allowing the keys `allowed`.
  Section below(const toml::table& t, const std::string& path, std::vector<std::string> allowed) const {
    return Section(t, key_of(path), loc_, std::move(allowed));
  }
  const toml::node* get(const std::string& k) const { return t_.get(k); }
  bool has(const std::string& k) const { return t_.contains(k); }
  [[noreturn]] void fail(const std::string& k, const std::string& what) const {
    const toml::node* n = get(k);
    loc_.fail(n ? n : (path_.empty() ? nullptr : &t_), key_of(k),
              what);  // the document's line 1 would mislead
  }

  double number(const std::string& k, double fallback) const {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_number()) fail(k, "expected a number, got " + describe(*n));
    if (!std::isfinite(number_value(*n))) fail(k, "expected a finite number, got " + describe(*n));
    return number_value(*n);
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
  /// A name other keys and the messages refer to (a material, a body, a rigid body): at most 64 characters.
  std::string name(const std::string& k, const std::string& fallback) const {
    const std::string v = text(k, fallback);
    if (v.size() > 64) fail(k, "expected a name of at most 64 characters, got " + in_quotes(v));
    return v;
  }
  std::string choice(const std::string& k, const std::string& fallback,
                     const std::vector<std::string>& options) const {
    const std::string v = text(k, fallback);
    if (std::find(options.begin(), options.end(), v) == options.end())
      fail(k, "expected one of " + join(options) + ", got " + in_quotes(v));
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
      if (!e.is_number() || !std::isfinite(number_value(e)))
        fail(k,
             "expected an array of " + std::to_string(n) + " finite numbers, got " + describe(e) + " in it");
      out.push_back(number_value(e));
    }
    return out;
  }
  /// An array of n components, each a number or an expression string over `vars`.
  std::vector<ExpressionPtr> expressions(const std::string& k, std::size_t n,
                                         const std::vector<std::string>& vars,
                                         const std::map<std::string, double>& constants) const {
    const std::string what = "an array of " + std::to_string(n) + " numbers or expression strings of " +
                             (vars.empty() ? std::string("nothing") : join(vars));
    const toml::array& a = array(k, n, what);
    std::vector<ExpressionPtr> out;
    for (std::size_t c = 0; c < a.size(); ++c) {
      const toml::node& e = *a.get(c);
      const std::optional<std::string> src = expression_source(e);
      if (!src) fail(k, "expected " + what + ", got " + describe(e) + " in it");
      out.push_back(std::make_shared<Expression>(*src, vars, constants,
                                                 loc_.where(&e, key_of(k) + "[" + std::to_string(c) + "]")));
    }
    return out;
  }
  /// One number or expression string over `vars`.
  ExpressionPtr expression(const std::string& k, const std::vector<std::string>& vars,
                           const std::map<std::string, double>& constants) const {
    const toml::node* n = get(k);
    const std::optional<std::string> src = n ? expression_source(*n) : std::nullopt;
    if (!src)
      fail(k, "expected a number or an expression string of " +
                  (vars.empty() ? std::string("nothing") : join(vars)) + (n ? ", got " + describe(*n) : ""));
    return std::make_shared<Expression>(*src, vars, constants, loc_.where(n, key_of(k)));
  }
  /// An array of n numbers, each written as a number or an expression string of the constants alone (e.g.
  /// "9.81 * sin(theta * pi / 180)"), evaluated once.
  std::vector<double> constant_numbers(const std::string& k, std::size_t n,
                                       const std::map<std::string, double>& constants) const {
    std::vector<double> out;
    for (const ExpressionPtr& e : expressions(k, n, {}, constants)) {
      out.push_back((*e)({}));
      if (!std::isfinite(out.back())) fail(k, "expected finite values, got " + std::to_string(out.back()));
    }
    return out;
  }
  /// One number written as a number or an expression string of the constants alone; `fallback` when absent.
  double constant_number(const std::string& k, double fallback,
                         const std::map<std::string, double>& constants) const {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (n->is_number()) return number(k, fallback);
    if (!n->is_string())
      fail(k, "expected a number or an expression string of the constants, got " + describe(*n));
    const double v = Expression(n->value<std::string>().value(), {}, constants, loc_.where(n, key_of(k)))({});
    if (!std::isfinite(v)) fail(k, "expected a finite value, got " + std::to_string(v));
    return v;
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
  /// The text of an expression written as a number (to 17 digits) or a string; none for any other node.
  static std::optional<std::string> expression_source(const toml::node& e) {
    if (e.is_string()) return e.value<std::string>().value();
    if (!e.is_number()) return std::nullopt;
    std::ostringstream os;
    os.precision(17);
    os << number_value(e);
    return os.str();
  }

  const toml::table& t_;
  std::string path_;
  const Locator& loc_;
  std::vector<std::string> allowed_;
};

inline const std::vector<std::string> position_vars[] = {{"x"}, {"x", "y"}, {"x", "y", "z"}};
inline const std::vector<std::string> reference_vars[] = {{"X"}, {"X", "Y"}, {"X", "Y", "Z"}};
inline const std::vector<std::string> reference_time_vars[] = {
    {"X", "t"}, {"X", "Y", "t"}, {"X", "Y", "Z", "t"}};
inline const std::vector<std::string> time_var{"t"};

/// The deepest a key of a scene may nest: the segments of a dotted key or table header, or of a --set path.
inline constexpr std::size_t max_key_depth = 64;
/// Throw InputError ("FILE:LINE: a key nested deeper than ...") if a key of a scene's text nests deeper than
/// max_key_depth, before toml++ parses it (its parser recurses once per segment).
void refuse_deep_keys(std::string_view text, const std::string& file);

/// Read one [[materials]] table into sc.materials.
void read_material(const Section& s, Scene& sc);
/// Every key a [[materials]] table may hold (those of the laws that declare theirs included).
std::vector<std::string> material_keys();
/// The corners `lo` and `hi` of a box inside the grid (`past_symmetry`: or reaching past it across its
/// symmetry faces only), each component a number or an expression of the constants; `what` names it in the
/// message ("the box").
void read_box(const Section& s, const Scene& sc, const std::string& what, std::vector<double>& lo,
              std::vector<double>& hi, bool past_symmetry = false);
/// What a shape belongs to: a body (a particle file or a Gmsh mesh allowed), a shape a body adds, subtracts
/// or intersects, or a rigid body. A body's shapes may reach past the grid across its symmetry faces, the
/// body being their part inside (a quarter of a ring about two symmetry planes); a rigid body lies inside.
enum class ShapeOwner { body, body_part, rigid_body };
/// Where a body or a rigid body lies: its `shape` and that shape's keys, and `ppc`; `box` names a box in the
/// message ("the box").
void read_shape(const Section& s, const Scene& sc, const std::string& box, ShapeOwner owner, SceneShape& out);
/// Read bodies[index] into sc.bodies.
void read_body(const Section& s, Scene& sc, std::size_t index);
/// A polygon body's outline from its `vertices` (inline [x, y] pairs or a file of them), refused with one
/// line where it bounds no region (fewer than 3 vertices, repeated vertices, edges that cross or touch).
Polygon read_outline(const Section& s, const Scene& sc);
/// A surface body's closed triangulated surface from `file` (STL or OBJ), times `scale`, moved by
/// `translate`; refused with one line where the file cannot be read or the surface has a hole.
TriangleSurface read_surface(const Section& s, const Scene& sc, const std::filesystem::path& file);
/// A mesh body's particles: the Gauss points of the elements of the scene's dimension in the Gmsh mesh
/// `file` (a rule exact to degree `quadrature`; 0: 2 on simplices, 3 on quadrangles and hexahedra), each with
/// the material its element's physical group has in `groups` (group name, or number when unnamed, to material
/// index), else `fallback`. Refused with one line at `file` or `materials` where Gmsh cannot read the file,
/// it holds no such element, an element is degenerate, a 2-D mesh leaves the plane z = 0, a group named is
/// not in the mesh, or an element has no material.
std::vector<MeshPoint> read_mesh(const Section& s, const Scene& sc, const std::filesystem::path& file,
                                 int quadrature, const std::map<std::string, std::size_t>& groups,
                                 std::optional<std::size_t> fallback);
/// Read rigid_bodies[index] into sc.rigid_bodies.
void read_rigid_body(const Section& s, Scene& sc, std::size_t index);
/// Read one [[contact]] table into sc.contacts (after the bodies and rigid bodies).
void read_contact(const Section& s, Scene& sc);
/// The velocity field of each body from the [[contact]] tables (Scene::body_field, Scene::fields).
void assign_fields(Scene& sc);
/// Read the [loads] table.
void read_loads(const Section& s, Scene& sc, const Locator& loc);

}  // namespace mpm::scene_reading

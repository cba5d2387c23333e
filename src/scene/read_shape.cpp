// Reading where a body or a rigid body lies: a box, a disk or sphere, a ring, a polygon, a closed surface or
// (bodies) a particle file or a Gmsh mesh, inside the grid.
#include <filesystem>
#include <sstream>
#include <system_error>

#include "mpm/scene/budget.hpp"
#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// Empty when [lo, hi] lies inside the grid (`past_symmetry`: or leaves it only across symmetry faces), else
/// "lo" or "hi" (the side that leaves it).
std::string outside_grid(const Scene& sc, const std::vector<double>& lo, const std::vector<double>& hi,
                         bool past_symmetry) {
  const auto across = [&](int face) {
    return !past_symmetry || sc.faces[face].kind != SceneFace::Kind::symmetry;
  };
  for (int d = 0; d < sc.dim; ++d)
    if (lo[d] < sc.grid_lo[d] - 1e-12 && across(2 * d)) return "lo";
  for (int d = 0; d < sc.dim; ++d)
    if (hi[d] > sc.grid_hi[d] + 1e-12 && across(2 * d + 1)) return "hi";
  for (int d = 0; d < sc.dim; ++d)  // reaching past a symmetry face, but not into the grid
    if (hi[d] <= sc.grid_lo[d] || lo[d] >= sc.grid_hi[d]) return hi[d] <= sc.grid_lo[d] ? "hi" : "lo";
  return "";
}

/// The grid's extent for messages, e.g. "[0, 1] x [0, 2]", and, when a shape may cross them, its symmetry
/// faces.
std::string grid_extent(const Scene& sc, bool past_symmetry = false) {
  std::ostringstream os;
  for (int d = 0; d < sc.dim; ++d) os << (d ? " x [" : "[") << sc.grid_lo[d] << ", " << sc.grid_hi[d] << "]";
  std::string symmetry;
  for (int f = 0; past_symmetry && f < 2 * sc.dim; ++f)
    if (sc.faces[f].kind == SceneFace::Kind::symmetry)
      symmetry += (symmetry.empty() ? "" : ", ") + std::string(face_names[f]);
  if (!symmetry.empty()) os << " (or reach past its symmetry faces: " << symmetry << ")";
  return os.str();
}

/// The regular file `file` names (relative to the scene's folder); `what` says what it should hold.
std::filesystem::path existing_file(const Section& s, const Scene& sc, const std::string& what) {
  std::filesystem::path file = s.text("file", "");
  if (file.empty()) s.fail("file", "missing (" + what + ")");
  if (file.is_relative()) file = sc.file.parent_path() / file;
  std::error_code ec;  // a name the file system refuses (too long, say) is an error, not an exception
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status))
    s.fail("file", "cannot open " + in_quotes(file.string()) + (ec ? " (" + ec.message() + ")" : ""));
  if (!std::filesystem::is_regular_file(status))
    s.fail("file", in_quotes(file.string()) + " is not a regular file (" + what + ")");
  return file;
}

}  // namespace

/// The corners `lo` and `hi` of a box inside the grid, each component a number or an expression of the
/// constants; `what` names it in the message ("the box").
void read_box(const Section& s, const Scene& sc, const std::string& what, std::vector<double>& lo,
              std::vector<double>& hi, bool past_symmetry) {
  const auto n = static_cast<std::size_t>(sc.dim);
  lo = s.constant_numbers("lo", n, sc.constants);
  hi = s.constant_numbers("hi", n, sc.constants);
  for (std::size_t d = 0; d < n; ++d)
    if (!(hi[d] > lo[d])) s.fail("hi", "expected hi > lo on every axis");
  const std::string side = outside_grid(sc, lo, hi, past_symmetry);
  if (!side.empty()) s.fail(side, what + " must lie inside the grid " + grid_extent(sc, past_symmetry));
}
void read_shape(const Section& s, const Scene& sc, const std::string& box, ShapeOwner owner,
                SceneShape& out) {
  const auto n = static_cast<std::size_t>(sc.dim);
  const bool past = owner != ShapeOwner::rigid_body;  // a body's shapes may reach past its symmetry faces
  std::vector<std::string> shapes{"box", "disk", "sphere", "ring", "polygon", "surface"};
  if (owner == ShapeOwner::body) shapes.insert(shapes.end(), {"file", "mesh"});
  const std::string shape = s.choice("shape", "box", shapes);
  if (shape == "box") {
    out.shape = SceneShape::Shape::box;
    read_box(s, sc, box, out.lo, out.hi, past);
  } else if (shape == "polygon") {
    if (sc.dim != 2) s.fail("shape", "\"polygon\" is for 2-D scenes");
    out.shape = SceneShape::Shape::polygon;
    out.polygon = read_outline(s, sc);
    const auto [lo, hi] = out.polygon.bounds();
    if (!outside_grid(sc, {lo[0], lo[1]}, {hi[0], hi[1]}, past).empty())
      s.fail("vertices", "the polygon must lie inside the grid " + grid_extent(sc, past));
  } else if (shape == "surface") {
    if (sc.dim != 3) s.fail("shape", "\"surface\" is for 3-D scenes");
    out.shape = SceneShape::Shape::surface;
    std::filesystem::path file = s.text("file", "");
    if (file.empty()) s.fail("file", "missing (an STL or OBJ file of the closed surface)");
    if (file.is_relative()) file = sc.file.parent_path() / file;
    out.surface = read_surface(s, sc, file);
    const auto [lo, hi] = out.surface.bounds();
    if (!outside_grid(sc, {lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, past).empty())
      s.fail("file", "the surface (scaled and translated) must lie inside the grid " + grid_extent(sc, past));
  } else if (shape == "file") {
    out.shape = SceneShape::Shape::file;
    out.file = existing_file(s, sc, "a particle file: CSV, or HDF5 named *.h5 or *.hdf5");
  } else if (shape == "mesh") {
    if (sc.dim == 1) s.fail("shape", "\"mesh\" needs a 2-D or 3-D scene");
    out.shape = SceneShape::Shape::mesh;
    out.file = existing_file(s, sc, "a Gmsh mesh, .msh");
    // Gmsh reads a file by its extension, and runs a .geo script's commands: only meshes are read.
    if (out.file.extension() != ".msh")
      s.fail("file", in_quotes(out.file.string()) + ": expected a Gmsh mesh file, named *.msh");
  } else {
    if ((shape == "disk" && sc.dim != 2) || (shape == "sphere" && sc.dim != 3))
      s.fail("shape", "\"disk\" is for 2-D scenes, \"sphere\" for 3-D");
    if (shape == "ring" && sc.dim == 1) s.fail("shape", "\"ring\" needs a 2-D or 3-D scene");
    out.shape = shape == "ring" ? SceneShape::Shape::ring : SceneShape::Shape::disk;
    out.center = s.numbers("center", n);
    out.radius = s.required_number("radius");
    if (!(out.radius > 0)) s.fail("radius", "expected a positive radius [m]");
    if (out.shape == SceneShape::Shape::ring) {
      out.inner_radius = s.required_number("inner_radius");
      if (!(out.inner_radius >= 0 && out.inner_radius < out.radius))
        s.fail("inner_radius", "expected 0 <= inner_radius < radius");
    }
    std::vector<double> lo = out.center, hi = out.center;
    for (std::size_t d = 0; d < n; ++d) lo[d] -= out.radius, hi[d] += out.radius;
    if (!outside_grid(sc, lo, hi, past).empty())
      s.fail("radius",
             "the " + shape + " (center +- radius) must lie inside the grid " + grid_extent(sc, past));
  }
  out.ppc = s.integer("ppc", 2);
  if (out.ppc < 1 || out.ppc > limits::max_ppc)
    s.fail("ppc", "expected at least 1 and at most " + std::to_string(limits::max_ppc) +
                      (owner == ShapeOwner::rigid_body ? " points" : " particles") + " per cell per axis");
}

}  // namespace mpm::scene_reading

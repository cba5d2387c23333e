// Reading a mesh body: the Gauss points of a Gmsh mesh's elements (any element type and order Gmsh knows,
// any .msh version), each a particle of the material of its element's physical group. Gmsh reads the file
// (gmsh_library.hpp).
#include <algorithm>
#include <cmath>

#include "gmsh_library.hpp"
#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// A physical group's name as a scene names it: its name in the file, or its number when it has none.
std::string group_name(const GmshSession& gmsh, int dim, int tag) {
  const std::string name = gmsh.physical_name(dim, tag);
  return name.empty() ? std::to_string(tag) : name;
}
}  // namespace

std::vector<MeshPoint> read_mesh(const Section& s, const Scene& sc, const std::filesystem::path& file,
                                 int quadrature, const std::map<std::string, std::size_t>& groups,
                                 std::optional<std::size_t> fallback) {
  const std::string named = in_quotes(file.string());
  std::vector<MeshPoint> points;
  Real extent = 0, off_plane = 0;
  try {
    const GmshSession gmsh;
    try {
      gmsh.open(file.string());
    } catch (const GmshError& e) {
      s.fail("file", "Gmsh cannot read " + named + ": " + e.what());
    }
    const std::vector<std::pair<int, int>> entities = gmsh.entities(sc.dim);
    const std::string elements = std::to_string(sc.dim) + "-D elements";
    if (entities.empty()) s.fail("file", named + " holds no " + elements + " (a Gmsh mesh, .msh)");
    std::vector<std::string> names;
    for (const auto& [dim, tag] : gmsh.physical_groups(sc.dim)) names.push_back(group_name(gmsh, dim, tag));
    for (const auto& [group, material] : groups)
      if (std::find(names.begin(), names.end(), group) == names.end())
        s.fail("materials",
               named + " has no physical group " + in_quotes(group) + " of " + elements +
                   (names.empty() ? std::string(" (it has none)") : " (it has: " + join(names) + ")"));
    for (const auto& [dim, entity] : entities) {
      const std::vector<int> tags = gmsh.physical_groups_of_entity(dim, entity);
      if (tags.size() > 1)
        s.fail("file", named + ": the " + elements + " of entity " + std::to_string(entity) +
                           " lie in two physical groups, " + in_quotes(group_name(gmsh, dim, tags[0])) +
                           " and " + in_quotes(group_name(gmsh, dim, tags[1])) + " (one material each)");
      const std::string group = tags.empty() ? "" : group_name(gmsh, dim, tags[0]);
      const auto mapped = groups.find(group);
      if (mapped == groups.end() && !fallback)
        s.fail("materials",
               "the " + elements + " of " +
                   (group.empty() ? "entity " + std::to_string(entity) + ", in no physical group,"
                                  : "physical group " + in_quotes(group)) +
                   " of " + named + " have no material: name the group here, or give the body a material");
      const std::size_t material = mapped != groups.end() ? mapped->second : *fallback;
      for (const int type : gmsh.element_types(dim, entity)) {
        // Gmsh's Gauss rule exact for polynomials of degree `quadrature` on this element type (by default 2
        // on simplices: 3 points on a triangle, 4 on a tetrahedron; 3 on quadrangles and hexahedra:
        // Gauss-Legendre 2 x 2 and 2 x 2 x 2), and each element's Jacobian determinants and positions at its
        // points.
        const std::string element = gmsh.element_name(type);
        const bool tensor = element.starts_with("Quadrilateral") || element.starts_with("Hexahedron");
        const int degree = quadrature > 0 ? quadrature : tensor ? 3 : 2;
        const auto [local, weights] = gmsh.integration_points(type, "Gauss" + std::to_string(degree));
        if (weights.empty() || std::any_of(weights.begin(), weights.end(), [](double w) { return !(w > 0); }))
          s.fail("quadrature", "Gmsh's Gauss rule of degree " + std::to_string(degree) + " on " + element +
                                   " elements has a weight <= 0, which no particle can carry: choose another "
                                   "degree");
        const auto [determinants, x] = gmsh.jacobians(type, local, entity);
        const std::vector<std::size_t> element_tags = gmsh.elements(type, entity);
        for (std::size_t k = 0; k < determinants.size(); ++k) {
          MeshPoint p;
          p.volume = weights[k % weights.size()] * std::abs(determinants[k]);
          if (!(p.volume > 0))  // a zero Jacobian
            s.fail("file", named + ": element " + std::to_string(element_tags[k / weights.size()]) +
                               " is degenerate (a Gauss point of zero volume)");
          for (std::size_t d = 0; d < 3; ++d) {
            p.x[d] = x[3 * k + d];
            extent = std::max(extent, std::abs(p.x[d]));
          }
          off_plane = std::max(off_plane, std::abs(p.x[2]));
          p.material = material;
          points.push_back(p);
        }
      }
    }
  } catch (const GmshError& e) {
    s.fail("file", "Gmsh failed on " + named + ": " + e.what());
  }
  if (points.empty())
    s.fail("file", named + " holds no " + std::to_string(sc.dim) + "-D elements (a Gmsh mesh, .msh)");
  if (sc.dim == 2 && off_plane > 1e-9 * extent)
    s.fail("file", named + ": a 2-D scene's mesh lies in the plane z = 0 (its elements reach z = " +
                       std::to_string(off_plane) + ")");
  return points;
}

}  // namespace mpm::scene_reading

// Reading a polygon body's outline: inline vertices or a file of them, refused where it bounds no region.
#include <fstream>
#include <sstream>
#include <system_error>

#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// The most vertices an outline may have: the check that it does not cross itself compares every pair of
/// edges.
constexpr std::size_t max_vertices = 20'000;

/// The vertices of a file: one "x, y" (or "x y") per line; empty lines and lines starting with '#' skipped,
/// a first line of words taken as a header.
std::vector<Vec<2>> read_vertex_file(const Section& s, const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    s.fail("vertices", "cannot open " + in_quotes(file.string()) + " (a file of x, y vertices)");
  std::ifstream is(file);
  std::vector<Vec<2>> out;
  std::string line;
  for (int line_no = 1; std::getline(is, line); ++line_no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // a file with Windows line ends
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    if (line_no == 1 && std::isalpha(static_cast<unsigned char>(line[start]))) continue;
    std::string fields = line;
    for (char& c : fields)
      if (c == ',') c = ' ';
    std::istringstream row(fields);
    Vec<2> v;
    std::string rest;
    if (!(row >> v[0] >> v[1]) || (row >> rest) || !v.allFinite())
      s.fail("vertices", file.string() + ":" + std::to_string(line_no) +
                             ": expected two finite numbers x, y, got " + in_quotes(shortened(line)));
    out.push_back(v);
    if (out.size() > max_vertices)
      s.fail("vertices",
             in_quotes(file.string()) + " has more than " + std::to_string(max_vertices) + " vertices");
  }
  return out;
}

/// The vertices given inline: an array of [x, y] pairs.
std::vector<Vec<2>> read_inline_vertices(const Section& s, const toml::array& a) {
  if (a.size() > max_vertices) s.fail("vertices", "more than " + std::to_string(max_vertices) + " vertices");
  std::vector<Vec<2>> out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const toml::array* pair = a[k].as_array();
    const bool numbers = pair && pair->size() == 2 && (*pair)[0].is_number() && (*pair)[1].is_number();
    const Vec<2> v = numbers ? Vec<2>(number_value((*pair)[0]), number_value((*pair)[1])) : Vec<2>::Zero();
    if (!numbers || !v.allFinite())
      s.fail("vertices", "vertex " + std::to_string(k) + ": expected a pair [x, y] of finite numbers, got " +
                             describe(a[k]));
    out.push_back(v);
  }
  return out;
}
}  // namespace

Polygon read_outline(const Section& s, const Scene& sc) {
  const toml::node* node = s.get("vertices");
  if (!node || !(node->is_array() || node->is_string()))
    s.fail("vertices", "expected an array of [x, y] pairs, or the name of a file of them" +
                           (node ? ", got " + describe(*node) : std::string()));
  Polygon polygon;
  if (node->is_string()) {
    std::filesystem::path file = node->value<std::string>().value();
    if (file.is_relative()) file = sc.file.parent_path() / file;
    polygon.vertices = read_vertex_file(s, file);
  } else {
    polygon.vertices = read_inline_vertices(s, *node->as_array());
  }
  std::vector<Vec<2>>& v = polygon.vertices;
  if (v.size() > 1 && v.front() == v.back()) v.pop_back();  // an outline closed by repeating its first vertex
  if (v.size() < 3) s.fail("vertices", "expected at least 3 vertices, got " + std::to_string(v.size()));
  for (std::size_t k = 0; k < v.size(); ++k)
    if (v[k] == v[(k + 1) % v.size()])
      s.fail("vertices",
             "vertices " + std::to_string(k) + " and " + std::to_string((k + 1) % v.size()) + " coincide");
  if (const auto crossing = first_crossing(polygon))
    s.fail("vertices", "edges " + std::to_string(crossing->first) + " and " +
                           std::to_string(crossing->second) +
                           " meet (edge k joins vertex k to vertex k + 1): the outline must not cross or "
                           "touch itself");
  return polygon;
}

}  // namespace mpm::scene_reading

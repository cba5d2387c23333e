#include "mpm/geometry/surface.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace mpm {

namespace {
/// Whether the point p = (0, 0) of the yz-plane lies to the left of the line from a to b (a and b relative to
/// p): the sign of (a - p) x (b - p). On the line, p is nudged to (eps, eps^2), which adds eps (a_1 - b_1) +
/// eps^2 (b_0 - a_0) to it (simulation of simplicity, Edelsbrunner & Muecke 1990), so that of two triangles
/// sharing the edge exactly one counts it: the sign for (b, a) is always the opposite, in floating point too
/// (the products are the same and x - y = -(y - x)).
bool left_of(const Vec<2>& a, const Vec<2>& b) {
  const Real side = a[0] * b[1] - a[1] * b[0];
  if (side != 0) return side > 0;
  if (a[1] != b[1]) return a[1] - b[1] > 0;
  return b[0] - a[0] > 0;
}
}  // namespace

std::vector<Real> TriangleSurface::crossings(Real y, Real z) const {
  std::vector<Real> out;
  for (const std::array<std::int32_t, 3>& f : faces) {
    const Vec<3>& a = vertices[f[0]];
    const Vec<3>& b = vertices[f[1]];
    const Vec<3>& c = vertices[f[2]];
    const Vec<2> pa(a[1] - y, a[2] - z), pb(b[1] - y, b[2] - z), pc(c[1] - y, c[2] - z);
    const bool l1 = left_of(pa, pb), l2 = left_of(pb, pc), l3 = left_of(pc, pa);
    if (l1 != l2 || l2 != l3) continue;  // the line passes beside the triangle's projection
    // Where the line meets the triangle's plane: n . (x - a) = 0 with x = (t, y, z).
    const Vec<3> n = (b - a).cross(c - a);
    if (n[0] == 0) continue;  // the triangle lies along the line (its projection has no area)
    out.push_back(a[0] - (n[1] * (y - a[1]) + n[2] * (z - a[2])) / n[0]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

Real TriangleSurface::volume() const {
  Real six = 0;  // sum of a . (b x c): six times the signed volume
  for (const std::array<std::int32_t, 3>& f : faces)
    six += vertices[f[0]].dot(vertices[f[1]].cross(vertices[f[2]]));
  return std::abs(six) / 6;
}

Vec<3> TriangleSurface::centroid() const {
  // The tetrahedra from the origin to each triangle: volume a . (b x c) / 6, centroid (a + b + c) / 4.
  Real six = 0;
  Vec<3> moment = Vec<3>::Zero();
  for (const std::array<std::int32_t, 3>& f : faces) {
    const Vec<3>& a = vertices[f[0]];
    const Vec<3>& b = vertices[f[1]];
    const Vec<3>& c = vertices[f[2]];
    const Real v = a.dot(b.cross(c));
    six += v;
    moment += v * (a + b + c);
  }
  return moment / (4 * six);
}

Real TriangleSurface::area() const {
  Real twice = 0;
  for (const std::array<std::int32_t, 3>& f : faces)
    twice += (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]).norm();
  return twice / 2;
}

std::pair<Vec<3>, Vec<3>> TriangleSurface::bounds() const {
  Vec<3> lo = vertices.front(), hi = vertices.front();
  for (const Vec<3>& v : vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo, hi};
}

std::size_t weld(TriangleSurface& s) {
  const auto less = [](const Vec<3>& a, const Vec<3>& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::map<Vec<3>, std::int32_t, decltype(less)> index(less);
  std::vector<Vec<3>> kept;
  std::vector<std::int32_t> to(s.vertices.size());
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const auto [it, added] = index.emplace(s.vertices[i], static_cast<std::int32_t>(kept.size()));
    if (added) kept.push_back(s.vertices[i]);
    to[i] = it->second;
  }
  std::vector<std::array<std::int32_t, 3>> faces;
  for (const std::array<std::int32_t, 3>& f : s.faces) {
    const std::array<std::int32_t, 3> g{to[f[0]], to[f[1]], to[f[2]]};
    if (g[0] != g[1] && g[1] != g[2] && g[2] != g[0]) faces.push_back(g);
  }
  const std::size_t dropped = s.faces.size() - faces.size();
  s.vertices = std::move(kept);
  s.faces = std::move(faces);
  return dropped;
}

std::optional<std::string> closure_defect(const TriangleSurface& s) {
  std::map<std::pair<std::int32_t, std::int32_t>, int> uses;
  for (const std::array<std::int32_t, 3>& f : s.faces)
    for (int e = 0; e < 3; ++e) {
      const std::int32_t a = f[e], b = f[(e + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [edge, count] : uses) {
    if (count % 2 == 0) continue;
    std::ostringstream os;
    os.precision(9);
    const Vec<3>& a = s.vertices[edge.first];
    const Vec<3>& b = s.vertices[edge.second];
    os << "the surface is not closed: the edge from (" << a[0] << ", " << a[1] << ", " << a[2] << ") to ("
       << b[0] << ", " << b[1] << ", " << b[2] << ") belongs to " << count
       << (count == 1 ? " triangle" : " triangles");
    return os.str();
  }
  return std::nullopt;
}

}  // namespace mpm

#include "mpm/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mpm {

namespace {
/// The cross product (b - a) x (c - a): positive when c lies to the left of the line from a to b.
Real orientation(const Vec<2>& a, const Vec<2>& b, const Vec<2>& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Whether c, collinear with a and b, lies in the box they span.
bool within(const Vec<2>& a, const Vec<2>& b, const Vec<2>& c) {
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

/// Whether the closed segments [a, b] and [c, d] share a point.
bool segments_meet(const Vec<2>& a, const Vec<2>& b, const Vec<2>& c, const Vec<2>& d) {
  const Real o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a),
             o4 = orientation(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
         (o4 == 0 && within(c, d, b));
}
}  // namespace

bool Polygon::contains(const Vec<2>& x) const {
  bool in = false;
  const std::size_t n = vertices.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec<2>& a = vertices[j];
    const Vec<2>& b = vertices[i];
    if ((a[1] <= x[1]) != (b[1] <= x[1])) {  // the edge spans the horizontal line through x
      const Real at = a[0] + (x[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
      if (x[0] < at) in = !in;
    }
  }
  return in;
}

Real Polygon::signed_area() const {
  Real twice = 0;
  const std::size_t n = vertices.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
    twice += vertices[j][0] * vertices[i][1] - vertices[i][0] * vertices[j][1];
  return 0.5 * twice;
}

Vec<2> Polygon::outward_normal(const Vec<2>& x) const {
  // Counter-clockwise, the region lies left of each edge a -> b, whose outward normal is (b - a) turned
  // clockwise.
  const Real sense = signed_area() > 0 ? 1 : -1;
  Real nearest_squared = std::numeric_limits<Real>::infinity();
  Vec<2> nearest = x, edge_normal = Vec<2>::Zero();
  const std::size_t n = vertices.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec<2> a = vertices[j], e = vertices[i] - vertices[j];
    const Vec<2> s = a + std::clamp((x - a).dot(e) / e.squaredNorm(), Real(0), Real(1)) * e;
    const Real d2 = (x - s).squaredNorm();
    if (d2 < nearest_squared) {
      nearest_squared = d2;
      nearest = s;
      edge_normal = sense * Vec<2>(e[1], -e[0]).normalized();
    }
  }
  const auto [lo, hi] = bounds();
  const Real distance = std::sqrt(nearest_squared);
  if (distance <= 1e-12 * (hi - lo).norm()) return edge_normal;
  const Vec<2> away = (x - nearest) / distance;
  return contains(x) ? Vec<2>(-away) : away;
}

Vec<2> Polygon::centroid() const {
  // The area-weighted centroids of the triangles each edge makes with the origin.
  Vec<2> moment = Vec<2>::Zero();
  Real twice = 0;
  const std::size_t n = vertices.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Real cross = vertices[j][0] * vertices[i][1] - vertices[i][0] * vertices[j][1];
    twice += cross;
    moment += cross * (vertices[j] + vertices[i]);
  }
  return moment / (3 * twice);
}

std::pair<Vec<2>, Vec<2>> Polygon::bounds() const {
  Vec<2> lo = vertices.front(), hi = vertices.front();
  for (const Vec<2>& v : vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo, hi};
}

std::optional<std::pair<std::size_t, std::size_t>> first_crossing(const Polygon& polygon) {
  const std::vector<Vec<2>>& v = polygon.vertices;
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      if (neighbours) {
        // Neighbours share a vertex; they must not overlap beyond it (an edge folding back on the last).
        const std::size_t shared = j == i + 1 ? j : i, far_i = j == i + 1 ? i : 1,
                          far_j = j == i + 1 ? (j + 1) % n : n - 1;
        const Vec<2>& s = v[shared];
        if (orientation(v[far_i], s, v[far_j]) == 0 && (v[far_i] - s).dot(v[far_j] - s) > 0) return {{i, j}};
        continue;
      }
      if (segments_meet(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n])) return {{i, j}};
    }
  return std::nullopt;
}

}  // namespace mpm

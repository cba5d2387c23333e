#include "mpm/geometry/surface_normal.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace mpm {

Vec<3> closest_on_triangle(const Vec<3>& p, const Vec<3>& a, const Vec<3>& b, const Vec<3>& c) {
  // Ericson 2005, Sec. 5.1.5: the vertex, edge or face region p projects into.
  const Vec<3> ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec<3> bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec<3> cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const Real denominator = 1 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

SurfaceNormal::SurfaceNormal(TriangleSurface surface) : surface_(std::move(surface)) {
  const auto [lo, hi] = surface_.bounds();
  size_ = (hi - lo).norm();
  // About one triangle a bucket along the longest side, and two buckets of margin beyond the box.
  const Real longest = (hi - lo).maxCoeff();
  const Real per_axis = std::max<Real>(1, std::cbrt(static_cast<Real>(surface_.faces.size())));
  cell_ = longest > 0 ? longest / per_axis : 1;
  lo_ = lo.array() - 2 * cell_;
  std::size_t count = 1;
  for (int d = 0; d < 3; ++d) {
    buckets_along_[d] = static_cast<int>(std::ceil((hi[d] - lo[d]) / cell_)) + 4;
    count *= static_cast<std::size_t>(buckets_along_[d]);
  }
  buckets_.resize(count);
  for (std::size_t k = 0; k < surface_.faces.size(); ++k) {
    Vec<3> a = surface_.vertices[surface_.faces[k][0]], z = a;
    for (int v = 1; v < 3; ++v) {
      a = a.cwiseMin(surface_.vertices[surface_.faces[k][v]]);
      z = z.cwiseMax(surface_.vertices[surface_.faces[k][v]]);
    }
    std::array<int, 3> first{}, last{};
    for (int d = 0; d < 3; ++d) {
      first[d] = std::clamp(static_cast<int>(std::floor((a[d] - lo_[d]) / cell_)), 0, buckets_along_[d] - 1);
      last[d] = std::clamp(static_cast<int>(std::floor((z[d] - lo_[d]) / cell_)), 0, buckets_along_[d] - 1);
    }
    for (int i = first[0]; i <= last[0]; ++i)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int l = first[2]; l <= last[2]; ++l)
          buckets_[(static_cast<std::size_t>(l) * buckets_along_[1] + j) * buckets_along_[0] + i].push_back(
              static_cast<std::int32_t>(k));
  }
  seen_.assign(surface_.faces.size(), 0);
}

std::array<int, 3> SurfaceNormal::bucket_of(const Vec<3>& x) const {
  std::array<int, 3> b{};
  for (int d = 0; d < 3; ++d) {
    const Real at = std::floor((x[d] - lo_[d]) / cell_);
    b[d] = at >= 0 && at < buckets_along_[d] ? static_cast<int>(at) : -1;
  }
  return b;
}

std::pair<std::int32_t, Vec<3>> SurfaceNormal::nearest(const Vec<3>& x) {
  if (++query_ == 0) {  // the counter wrapped: forget every visit
    std::fill(seen_.begin(), seen_.end(), 0);
    query_ = 1;
  }
  Real best = std::numeric_limits<Real>::infinity();
  std::int32_t best_k = -1;
  Vec<3> best_s = x;
  const auto visit = [&](std::int32_t k) {
    if (seen_[k] == query_) return;
    seen_[k] = query_;
    const std::array<std::int32_t, 3>& f = surface_.faces[k];
    const Vec<3> s =
        closest_on_triangle(x, surface_.vertices[f[0]], surface_.vertices[f[1]], surface_.vertices[f[2]]);
    const Real d2 = (x - s).squaredNorm();
    if (d2 < best) best = d2, best_k = k, best_s = s;
  };
  const std::array<int, 3> b = bucket_of(x);
  if (b[0] < 0 || b[1] < 0 || b[2] < 0) {  // beyond the buckets: every triangle
    for (std::size_t k = 0; k < surface_.faces.size(); ++k) visit(static_cast<std::int32_t>(k));
    return {best_k, best_s};
  }
  // Shells of buckets around x's, outward: a triangle not yet visited lies wholly in buckets farther than r
  // from x's, so more than r cells from x, and the search ends once the nearest found is closer than that.
  int reach = 0;
  for (int d = 0; d < 3; ++d) reach = std::max({reach, b[d], buckets_along_[d] - 1 - b[d]});
  for (int r = 0; r <= reach; ++r) {
    for (int l = std::max(0, b[2] - r); l <= std::min(buckets_along_[2] - 1, b[2] + r); ++l)
      for (int j = std::max(0, b[1] - r); j <= std::min(buckets_along_[1] - 1, b[1] + r); ++j)
        for (int i = std::max(0, b[0] - r); i <= std::min(buckets_along_[0] - 1, b[0] + r); ++i) {
          if (std::max({std::abs(i - b[0]), std::abs(j - b[1]), std::abs(l - b[2])}) != r) continue;
          for (const std::int32_t k :
               buckets_[(static_cast<std::size_t>(l) * buckets_along_[1] + j) * buckets_along_[0] + i])
            visit(k);
        }
    if (best_k >= 0 && std::sqrt(best) <= r * cell_) break;
  }
  return {best_k, best_s};
}

bool SurfaceNormal::inside(const Vec<3>& x) {
  if (!has_row_ || x[1] != row_y_ || x[2] != row_z_) {
    row_ = surface_.crossings(x[1], x[2]);
    row_y_ = x[1], row_z_ = x[2], has_row_ = true;
  }
  return (std::lower_bound(row_.begin(), row_.end(), x[0]) - row_.begin()) % 2 == 1;
}

Vec<3> SurfaceNormal::operator()(const Vec<3>& x) {
  const auto [k, s] = nearest(x);
  if (k < 0) return Vec<3>::Zero();  // no triangle
  const Vec<3> away = x - s;
  const Real distance = away.norm();
  if (distance > 1e-12 * size_) return (inside(x) ? Real(-1) : Real(1)) / distance * away;
  // On the surface: the triangle's normal, turned to the side a point just off it along it is outside on.
  const std::array<std::int32_t, 3>& f = surface_.faces[k];
  const Vec<3>& a = surface_.vertices[f[0]];
  const Vec<3> n = (surface_.vertices[f[1]] - a).cross(surface_.vertices[f[2]] - a);
  if (!(n.norm() > 0)) return Vec<3>::Zero();  // a sliver without a normal
  const Vec<3> unit = n.normalized();
  return inside(s + 1e-6 * size_ * unit) ? Vec<3>(-unit) : unit;
}

}  // namespace mpm

#pragma once
/// The outward normal of a closed triangulated surface at the point nearest a query point (a Coulomb rigid
/// body's normal at a grid node, RigidBody::outward), found among the triangles near the query.
#include <array>
#include <cstdint>
#include <vector>

#include "mpm/core/types.hpp"
#include "mpm/geometry/surface.hpp"

namespace mpm {

/// The closest point to p of the triangle (a, b, c), by the Voronoi regions of its vertices, edges and face
/// (Ericson 2005, Real-Time Collision Detection, Sec. 5.1.5).
Vec<3> closest_on_triangle(const Vec<3>& p, const Vec<3>& a, const Vec<3>& b, const Vec<3>& c);

/// The gradient of the distance to a closed surface, signed positive outside: (x - s) / |x - s| outside and
/// (s - x) / |s - x| inside for the nearest point s; on the surface (to 1e-12 of its size) the nearest
/// triangle's normal, turned outward. The triangles are kept in buckets of a uniform grid over the surface's
/// box, so a query visits those near it; inside is an odd number of crossings below x on the line parallel to
/// x through it (TriangleSurface::crossings), and the last line's crossings are kept for the next query on
/// the same line (a rigid body's nodes come row by row).
class SurfaceNormal {
 public:
  explicit SurfaceNormal(TriangleSurface surface);
  Vec<3> operator()(const Vec<3>& x);

 private:
  /// The nearest triangle's index and the nearest point.
  std::pair<std::int32_t, Vec<3>> nearest(const Vec<3>& x);
  bool inside(const Vec<3>& x);
  /// The bucket coordinates of x, or -1 on an axis where x lies beyond the buckets.
  std::array<int, 3> bucket_of(const Vec<3>& x) const;

  TriangleSurface surface_;
  Real size_ = 0;  ///< the diagonal of the surface's box [m]
  Vec<3> lo_ = Vec<3>::Zero();
  Real cell_ = 1;
  std::array<int, 3> buckets_along_{};
  std::vector<std::vector<std::int32_t>> buckets_;  ///< triangles whose box meets the bucket
  std::vector<std::uint32_t> seen_;                 ///< per triangle: the query that last visited it
  std::uint32_t query_ = 0;
  Real row_y_ = 0, row_z_ = 0;
  bool has_row_ = false;
  std::vector<Real> row_;  ///< the crossings of the line of the last inside test
};

}  // namespace mpm

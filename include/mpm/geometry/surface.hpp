#pragma once
/// A closed triangulated surface in space (a 3-D body's boundary, read from STL or OBJ): the inside test that
/// seeds its particles, its volume and centroid, and the check that refuses a surface with a hole.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mpm/core/types.hpp"

namespace mpm {

struct TriangleSurface {
  std::vector<Vec<3>> vertices;                    ///< [m]
  std::vector<std::array<std::int32_t, 3>> faces;  ///< indices into vertices, either way round

  /// The x at which the line parallel to x through (y, z) crosses the surface, in increasing order. A point
  /// (x, y, z) is inside when an odd number of them lie below x. A line through an edge or a vertex meets
  /// each of the triangles around it by one rule (the point is nudged to (y + eps, z + eps^2)), so it is
  /// counted once.
  std::vector<Real> crossings(Real y, Real z) const;
  /// The enclosed volume [m^3] (the divergence theorem over the triangles; positive either way round).
  Real volume() const;
  /// The centroid of the enclosed region [m].
  Vec<3> centroid() const;
  /// The surface's area [m^2].
  Real area() const;
  /// The lower and upper corners of the bounding box [m].
  std::pair<Vec<3>, Vec<3>> bounds() const;
};

/// Merge the vertices of equal coordinates (a file's triangles each list their own) and drop the triangles
/// that repeat a vertex; returns how many were dropped.
std::size_t weld(TriangleSurface& surface);

/// Why the surface does not bound a region, or nothing: an edge that an odd number of triangles share (a
/// hole, or a crack where the surface does not meet itself), named by its two vertices.
std::optional<std::string> closure_defect(const TriangleSurface& surface);

}  // namespace mpm

#pragma once
/// A simple polygon in the plane (a 2-D body's outline): the inside test that seeds its particles, its area
/// and centroid, and the checks that refuse an outline that does not bound a region.
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "mpm/core/types.hpp"

namespace mpm {

struct Polygon {
  std::vector<Vec<2>>
      vertices;  ///< in order around the outline, either way, the last joined to the first [m]

  /// Whether x lies inside, by the crossing number (an edge counts from its lower end, inclusive, to its
  /// upper end, exclusive, so that a point on a shared vertex is counted once).
  bool contains(const Vec<2>& x) const;
  /// The signed area, positive counter-clockwise [m^2] (the shoelace formula).
  Real signed_area() const;
  /// The centroid of the region [m].
  Vec<2> centroid() const;
  /// The lower and upper corners of the bounding box [m].
  std::pair<Vec<2>, Vec<2>> bounds() const;
  /// The outward unit normal of the outline at the point nearest x: the gradient of the distance to the
  /// outline, signed positive outside, i.e. (x - s) / |x - s| outside and (s - x) / |s - x| inside for the
  /// nearest point s; the nearest edge's outward normal for x on the outline (to 1e-12 of the polygon's
  /// size).
  Vec<2> outward_normal(const Vec<2>& x) const;
};

/// The first pair of edges (i, j), i < j, edge k joining vertex k to vertex k + 1, that cross or touch other
/// than at the vertex two neighbouring edges share; none for a simple polygon. O(n^2) in the vertices.
std::optional<std::pair<std::size_t, std::size_t>> first_crossing(const Polygon& polygon);

}  // namespace mpm

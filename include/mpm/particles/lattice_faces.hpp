#pragma once
/// The faces a particle of a body seeded on a lattice shows to the outside (particles/surface.hpp finds them;
/// boundary/surface_loads.hpp loads them), in a header of their own that needs no more than the types.
#include <array>

#include "mpm/core/types.hpp"

namespace mpm {

/// The faces of a particle's spacing-sized lattice cell that it shows to the outside: the area of face k =
/// 2 d + side (x-min, x-max, y-min, ...) when the neighbouring cell across it holds no particle of the body,
/// else zero; s^(Dim-1) (per unit thickness in 2-D; per radian in axisymmetry, where a face of the cell
/// around radius X_r has area r s, r = X_r +- s / 2 for the faces normal to the radius and X_r for the
/// others).
template <int Dim>
using LatticeFaces = std::array<Real, 2 * Dim>;

/// A particle's outward reference area vector N dA: the sum of its faces' outward normals times their areas.
/// The vectors of a closed surface sum to zero, and those of any part of it to the part's projected areas,
/// exactly; for a face inclined to the lattice the magnitude of each vector is the staircase's area, which is
/// the true area where the staircase steps evenly.
template <int Dim>
Vec<Dim> area_vector(const LatticeFaces<Dim>& faces) {
  Vec<Dim> a;
  for (int d = 0; d < Dim; ++d) a[d] = faces[2 * d + 1] - faces[2 * d];
  return a;
}

}  // namespace mpm

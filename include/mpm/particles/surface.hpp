#pragma once
/// The surface of a body seeded on a lattice: for each particle, the lattice-cell faces it shows to the
/// outside.
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

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

/// The lattice faces of each particle of a body: `X` its reference positions, `origin` any lattice point (a
/// cell centre), `spacing` s. Zero inside the body.
template <int Dim>
std::vector<LatticeFaces<Dim>> lattice_surface(const std::vector<Vec<Dim>>& X, const Vec<Dim>& origin,
                                               Real spacing, bool axisymmetric = false) {
  const auto cell_of = [&](const Vec<Dim>& x) {
    IVec<Dim> c;
    for (int d = 0; d < Dim; ++d) c[d] = static_cast<int>(std::lround((x[d] - origin[d]) / spacing));
    return c;
  };
  // Cells packed into one integer (21 bits an axis, offset to be positive): bodies far below 2^20 cells a
  // side.
  const auto key = [](const IVec<Dim>& c) {
    std::uint64_t k = 0;
    for (int d = 0; d < Dim; ++d) k = (k << 21) | static_cast<std::uint64_t>(c[d] + (1 << 20));
    return k;
  };
  std::unordered_set<std::uint64_t> occupied;
  occupied.reserve(X.size());
  for (const Vec<Dim>& x : X) occupied.insert(key(cell_of(x)));
  const Real face = std::pow(spacing, Dim - 1);
  std::vector<LatticeFaces<Dim>> faces(X.size(), LatticeFaces<Dim>{});
  for (std::size_t i = 0; i < X.size(); ++i) {
    const IVec<Dim> c = cell_of(X[i]);
    for (int d = 0; d < Dim; ++d)
      for (int side : {-1, 1}) {
        IVec<Dim> n = c;
        n[d] += side;
        if (occupied.count(key(n))) continue;
        const Real radius = !axisymmetric ? 1 : d == 0 ? X[i][0] + side * 0.5 * spacing : X[i][0];
        faces[i][2 * d + (side + 1) / 2] = face * radius;
      }
  }
  return faces;
}

}  // namespace mpm

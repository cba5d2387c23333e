#pragma once
/// The surface of a body seeded on a lattice: for each particle, the lattice-cell faces it shows to the
/// outside.
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "mpm/core/types.hpp"
#include "mpm/particles/lattice_faces.hpp"

namespace mpm {

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

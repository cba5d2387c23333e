#pragma once
/// The error at the grid nodes in the current configuration (Wallstedt & Guilkey 2008, App. A).
#include <cmath>

#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/verification/error_norms.hpp"

namespace mpm {

/// The reference position X of the material point at x at time t: the root of X + u_exact(X, t) = x
/// (Wallstedt & Guilkey 2008, Eq. (A.1)), by Newton's method with the Jacobian F = I + du/dX, from X = x.
/// The manufactured motions keep det F > 0 (their amplitudes are bounded), so the root is unique.
template <int Dim, class Exact>
Vec<Dim> reference_position(const Exact& exact, const Vec<Dim>& x, Real t) {
  Vec<Dim> X = x;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Vec<Dim> r = X + exact.displacement(X, t) - x;
    X -= exact.deformation_gradient(X, t).inverse() * r;
    if (r.norm() <= 1e-15 * (1 + x.norm())) break;
  }
  return X;
}

/// Record delta_i = |a_i - a_exact(X_i, t)| (Wallstedt & Guilkey 2008, Eq. (A.2)) at every node of the
/// physical domain that carries more than `min_mass`, with X_i from Eq. (A.1) and t the time the grid
/// acceleration a_i belongs to (the start of the step).
template <int Dim, class Exact>
void record_nodal_acceleration(ErrorNorms& error, const Grid<Dim>& grid, Real min_mass, Real t,
                               const Exact& exact) {
  const GridGeometry<Dim>& g = grid.geometry;
  for (std::size_t n = 0; n < grid.size(); ++n) {
    const GridNode<Dim>& node = grid.nodes[n];
    const Vec<Dim> x = g.position(g.coords(static_cast<std::ptrdiff_t>(n)));
    if (!(node.m > min_mass) || !g.contains(x)) continue;
    error.add((node.a - exact.acceleration(reference_position<Dim>(exact, x, t), t)).norm());
  }
}

}  // namespace mpm

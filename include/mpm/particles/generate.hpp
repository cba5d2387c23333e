#pragma once
/// Seeding particles on a regular lattice.
#include <cmath>
#include <cstdint>
#include <functional>

#include "mpm/core/errors.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// Fill the box [lo, hi] with particles on a lattice of the given spacing, one at the centre of each
/// spacing-sized sub-cell, keeping those whose centre satisfies `inside` (all when empty). Each particle gets
/// volume spacing^Dim, half-length spacing/2, mass density * volume and velocity `velocity(X)` (zero when
/// empty).
template <int Dim>
void fill_box(ParticleSet<Dim>& p, const Vec<Dim>& lo, const Vec<Dim>& hi, Real spacing, Real density,
              std::uint16_t material, const std::function<Vec<Dim>(const Vec<Dim>&)>& velocity = {},
              const std::function<bool(const Vec<Dim>&)>& inside = {}) {
  if (!(spacing > 0)) throw InputError("particle spacing must be positive");
  IVec<Dim> n;
  std::int64_t total = 1;
  for (int d = 0; d < Dim; ++d) {
    if (!(hi[d] > lo[d]))
      throw InputError("particle box: upper corner must exceed lower corner on every axis");
    n[d] = static_cast<int>(std::floor((hi[d] - lo[d]) / spacing + 1e-9));
    total *= n[d];
  }
  const Real volume = std::pow(spacing, Dim);
  const Vec<Dim> half = Vec<Dim>::Constant(0.5 * spacing);
  if (!inside) p.reserve(p.size() + static_cast<std::size_t>(total));  // arrays of the final size, grown once
  for (std::int64_t k = 0; k < total; ++k) {
    std::int64_t rest = k;
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) {
      x[d] = lo[d] + (static_cast<Real>(rest % n[d]) + 0.5) * spacing;
      rest /= n[d];
    }
    if (inside && !inside(x)) continue;
    p.add(x, velocity ? velocity(x) : Vec<Dim>::Zero(), density * volume, volume, half, material);
  }
}

}  // namespace mpm

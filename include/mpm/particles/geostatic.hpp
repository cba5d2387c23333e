#pragma once
/// The K0 procedure: a body starts in the geostatic stress of its own weight, the vertical stress from the
/// overburden above each particle and the horizontal stresses K0 times it.
#include <array>
#include <cmath>
#include <map>

#include "mpm/particles/particles.hpp"

namespace mpm {

/// Give particles [first, last) of p, a body of density rho seeded at `spacing`, the geostatic stress under
/// gravity g: sigma_v = -rho |g| depth along the vertical (-g), every horizontal normal stress (the
/// out-of-plane one too) K0 sigma_v, no shear. A particle's depth is measured from the body's free surface
/// above it: the top of the highest particle of the body in its column (columns of one spacing across, the
/// top half a spacing above that particle's centre). Sizes p.state to the particles and sets its stress.
template <int Dim>
void set_geostatic_stress(ParticleSet<Dim>& p, std::size_t first, std::size_t last, Real rho, Real k0,
                          const Vec<Dim>& g, Real spacing) {
  p.state.resize_keeping(p.size());
  const Vec<Dim> up = -g.normalized();
  const auto column = [&](const Vec<Dim>& x) {
    const Vec<Dim> across = x - x.dot(up) * up;
    std::array<long, Dim> key{};
    for (int d = 0; d < Dim; ++d) key[d] = std::lround(across[d] / spacing);
    return key;
  };
  std::map<std::array<long, Dim>, Real> surface;
  for (std::size_t i = first; i < last; ++i) {
    const Real top = p.x[i].dot(up) + 0.5 * spacing;
    const auto [at, fresh] = surface.try_emplace(column(p.x[i]), top);
    if (!fresh && top > at->second) at->second = top;
  }
  Eigen::Vector3d up3 = Eigen::Vector3d::Zero();
  for (int d = 0; d < Dim; ++d) up3[d] = up[d];
  for (std::size_t i = first; i < last; ++i) {
    const Real vertical = -rho * g.norm() * (surface.at(column(p.x[i])) - p.x[i].dot(up));
    const Eigen::Matrix3d sigma =
        k0 * vertical * Eigen::Matrix3d::Identity() + (1 - k0) * vertical * up3 * up3.transpose();
    for (int a = 0; a < 3; ++a)
      for (int c = a; c < 3; ++c) p.state.sigma[i](a, c) = sigma(a, c);
  }
}

}  // namespace mpm

#pragma once
/// Compressible Neo-Hookean solid.
#include <algorithm>
#include <cmath>

#include "mpm/core/simd.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

/// Compressible Neo-Hookean material with Lame constants lambda, mu and reference density rho0.
/// In 2-D the motion is plane strain (F_zz = 1); in 1-D it is uniaxial strain.
struct NeoHookean {
  Real lambda = 0;  ///< first Lame constant [Pa]
  Real mu = 0;      ///< shear modulus [Pa]
  Real rho0 = 0;    ///< reference density [kg/m^3]

  static NeoHookean from_young_poisson(Real E, Real nu, Real rho0) {
    return {E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), rho0};
  }

  /// Cauchy stress sigma = (lambda ln J I + mu (F F^T - I)) / J. Wallstedt & Guilkey 2008, Eq. (55).
  template <int Dim>
  [[gnu::always_inline]] inline SymTensor<Dim> stress(const Mat<Dim>& F, Real J) const {
    Real Fa[Dim][Dim], s[sym_size<Dim>];
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) Fa[a][b] = F(a, b);
    cauchy<Dim>(Fa, J, lambda, mu, s);
    SymTensor<Dim> out;
    for (int k = 0; k < sym_size<Dim>; ++k) out.c[k] = s[k];
    return out;
  }

  /// Wallstedt & Guilkey 2008, Eq. (55) for any number type T: one particle (Real) or several in SIMD lanes
  /// (simd::RealLanes), which give the same bits. s holds the components in SymTensor order.
  template <int Dim, class T>
  [[gnu::always_inline]] static inline void cauchy(const T (&F)[Dim][Dim], const T& J, const T& lambda,
                                                   const T& mu, T (&s)[sym_size<Dim>]) {
    const T inv_J = 1 / J;
    const T diag = (lambda * simd::log(J) - mu) * inv_J;
    for (int a = 0; a < Dim; ++a)
      for (int c = a; c < Dim; ++c) {
        T b_ac = F[a][0] * F[c][0];  // b = F F^T
        for (int k = 1; k < Dim; ++k) b_ac += F[a][k] * F[c][k];
        s[SymTensor<Dim>::index(a, c)] = a == c ? mu * inv_J * b_ac + diag : mu * inv_J * b_ac;
      }
  }

  /// Stored energy per reference volume, W = mu/2 (tr F^T F - 3) - mu ln J + lambda/2 (ln J)^2, whose
  /// derivative dW/dF is the first Piola-Kirchhoff stress of Wallstedt & Guilkey 2008, Eq. (54). Out-of-plane
  /// stretches are 1 (plane strain in 2-D, uniaxial strain in 1-D), so they add 3 - Dim to tr F^T F.
  template <int Dim>
  Real energy_density(const Mat<Dim>& F, Real J) const {
    const Real lnJ = std::log(J);
    return 0.5 * mu * (F.squaredNorm() - Dim) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
  }

  /// Dilatational wave speed at volume ratio J from the spatial tangent of Wallstedt & Guilkey 2008,
  /// Eq. (55): rho c^2 = (lambda + 2 (mu - lambda ln J)) / J with rho = rho0 / J.
  Real wave_speed(Real J) const {
    return std::sqrt(std::max(lambda + 2 * mu - 2 * lambda * std::log(J), mu) / rho0);
  }
};

}  // namespace mpm

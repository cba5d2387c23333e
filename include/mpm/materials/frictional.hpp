#pragma once
/// What the frictional (pressure-dependent) plasticity models of soils and rocks share: linear isotropic
/// elasticity, a strength of cohesion c and friction angle phi that soften or harden linearly with the
/// accumulated plastic strain, a dilatancy angle psi, and the step: the hypoelastic trial stress of the
/// rate-form laws (Jaumann rate, Sulsky & Kaul 2004, Sec. 2.2.4) returned to the yield surface by backward
/// Euler with the strength taken at the end of the step (de Souza Neto et al. 2008, Sec. 8.2 and Sec. 8.3).
///
/// Stresses are Cauchy stresses, tension positive; p = tr(sigma) / 3 is the mean stress (negative in
/// compression).
///
/// Accumulated plastic strain. eps_bar is the equivalent deviatoric plastic strain, d eps_bar =
/// (2/3 de_p : de_p)^{1/2} with de_p the deviator of the plastic strain increment: the same measure for both
/// yield surfaces, the plastic strain of a uniaxial test at constant volume, and zero for purely volumetric
/// flow (the Drucker-Prager apex or tension cut-off).
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/elastoplastic.hpp"
#include "mpm/materials/sym3.hpp"

namespace mpm {

/// Cohesion and friction angle, each linear in eps_bar from its initial value to its residual one, reached at
/// eps_bar = residual_strain and kept beyond (softening when the residual is lower, hardening when higher);
/// the dilatancy angle is constant.
struct FrictionalStrength {
  Real cohesion = 0;           ///< c0 [Pa]
  Real friction = 0;           ///< phi0 [rad]
  Real dilatancy = 0;          ///< psi [rad]: 0 flows at constant volume, psi = phi is associated flow
  Real residual_cohesion = 0;  ///< c_r [Pa]
  Real residual_friction = 0;  ///< phi_r [rad]
  Real residual_strain = 0;    ///< e_r > 0, or 0 when the strength is constant (c_r = c0, phi_r = phi0)

  bool constant() const { return residual_strain == 0; }
  /// The fraction of the way from the initial to the residual strength at plastic strain e.
  Real progress(Real e) const {
    if (constant()) return 0;
    return e >= residual_strain ? 1 : e / residual_strain;
  }
  Real cohesion_at(Real e) const { return cohesion + (residual_cohesion - cohesion) * progress(e); }
  Real friction_at(Real e) const { return friction + (residual_friction - friction) * progress(e); }
};

/// Check a strength; throw InputError naming `where` and the key (cohesion, friction_angle, dilatancy_angle,
/// residual_cohesion, residual_friction_angle, residual_strain).
void validate(const FrictionalStrength& s, const std::string& where);

/// Linear isotropic elasticity and the strength of a frictional material.
struct FrictionalSolid {
  Real E = 0;     ///< Young's modulus [Pa]
  Real nu = 0;    ///< Poisson's ratio
  Real rho0 = 0;  ///< reference density [kg/m^3]
  FrictionalStrength strength;

  Real lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }  ///< first Lame constant [Pa]
  Real mu() const { return E / (2 * (1 + nu)); }                      ///< shear modulus G [Pa]
  Real bulk() const { return E / (3 * (1 - 2 * nu)); }                ///< bulk modulus K [Pa]
  /// Dilatational wave speed sqrt((lambda + 2 mu)/rho) at current density rho [m/s].
  Real wave_speed(Real rho) const { return std::sqrt((lambda() + 2 * mu()) / rho); }
};

/// Check the elasticity and strength; throw InputError naming `where` and the key.
void validate(const FrictionalSolid& m, const std::string& where);

/// A trial stress returned to a yield surface whose strength is held fixed.
struct FrictionalReturn {
  Eigen::Matrix3d sigma;  ///< the stress after the return [Pa]
  bool plastic;           ///< whether the trial stress was outside the surface
};

/// The increment of eps_bar of a return from trial to sigma: de_p = C^-1 (trial - sigma), whose deviator is
/// dev(trial - sigma) / (2 G), so d eps_bar = |dev(trial - sigma)| / (sqrt(6) G). For one particle or lanes.
template <class T>
[[gnu::always_inline]] inline T plastic_strain_increment(const Sym3<T>& trial, const Sym3<T>& sigma,
                                                         const T& G) {
  Sym3<T> returned;
  for (int k = 0; k < 6; ++k) returned.c[k] = trial.c[k] - sigma.c[k];
  const Sym3<T> d = deviator(returned);
  return simd::sqrt(contract(d, d)) / (std::sqrt(6.0) * G);
}
inline Real plastic_strain_increment(const Eigen::Matrix3d& trial, const Eigen::Matrix3d& sigma, Real G) {
  return plastic_strain_increment(sym3_of(trial), sym3_of(sigma), G);
}

/// The plastic work density sigma : de_p of a return from trial to sigma with bulk modulus K and shear
/// modulus G: p (p_trial - p) / K + s : (s_trial - s) / (2 G).
Real plastic_work_density(const Eigen::Matrix3d& trial, const Eigen::Matrix3d& sigma, Real K, Real G);

/// The elastic trial stress of a step: the old stress rotated by the spin increment dW (Hughes & Winget 1980,
/// the Jaumann rate of Sulsky & Kaul 2004, Sec. 2.2.4) plus lambda tr(de) I + 2 mu de (Sulsky & Kaul 2004,
/// Eq. (2.2.21)).
Eigen::Matrix3d frictional_trial(const FrictionalSolid& m, const Eigen::Matrix3d& sigma_n,
                                 const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW);

/// Backward Euler with a softening strength: eps_bar_{n+1} = eps_n + d eps_bar(return at the strength of
/// eps_bar_{n+1}), solved for eps_bar_{n+1} by safeguarded regula falsi (Illinois) on [eps_n, e_r], where the
/// increment h(e) = eps_n + d eps_bar(e) - e changes sign; beyond e_r the strength is constant and one return
/// suffices. The stress returned lies on the surface of the eps_bar it reports. `at_strength(trial, e)`
/// returns trial to the surface of the strength at plastic strain e; the out-of-plane strain increment dz is
/// reported as given.
template <class ReturnAt>
StressUpdate return_with_softening(const FrictionalSolid& m, const Eigen::Matrix3d& trial, Real eps_n,
                                   Real dz, const ReturnAt& at_strength) {
  const Real G = m.mu(), K = m.bulk();
  const auto finish = [&](const FrictionalReturn& r, Real eps) {
    return StressUpdate{r.sigma, eps, r.plastic ? plastic_work_density(trial, r.sigma, K, G) : 0, dz,
                        r.plastic};
  };
  const FrictionalReturn first = at_strength(trial, eps_n);
  const Real e_r = m.strength.residual_strain;
  if (!first.plastic) return finish(first, eps_n);
  const auto h = [&](const FrictionalReturn& r, Real e) {
    return eps_n + plastic_strain_increment(trial, r.sigma, G) - e;
  };
  if (m.strength.constant() || eps_n >= e_r)
    return finish(first, eps_n + plastic_strain_increment(trial, first.sigma, G));
  const FrictionalReturn residual = at_strength(trial, e_r);
  const Real h_residual = h(residual, e_r);
  if (h_residual >= 0) return finish(residual, e_r + h_residual);
  // The root of h lies in [eps_n, e_r]: h(eps_n) >= 0 > h(e_r). Illinois regula falsi, stopped when h is
  // below 1e-14 of the plastic strain increment or the bracket cannot shrink.
  Real lo = eps_n, hi = e_r, h_lo = h(first, eps_n), h_hi = h_residual;
  FrictionalReturn best = first;
  Real e_best = eps_n, h_best = h_lo;
  int side = 0;
  for (int it = 0; it < 200 && h_best != 0; ++it) {
    Real e = (lo * h_hi - hi * h_lo) / (h_hi - h_lo);
    if (!(e > lo && e < hi)) e = 0.5 * (lo + hi);
    if (e == lo || e == hi) break;
    const FrictionalReturn r = at_strength(trial, e);
    const Real he = h(r, e);
    if (std::abs(he) < std::abs(h_best)) best = r, e_best = e, h_best = he;
    if (std::abs(he) <= 1e-14 * (e - eps_n)) break;
    if (he > 0) {
      lo = e, h_lo = he;
      if (side == 1) h_hi *= 0.5;
      side = 1;
    } else {
      hi = e, h_hi = he;
      if (side == -1) h_lo *= 0.5;
      side = -1;
    }
  }
  return finish(best, e_best);
}

}  // namespace mpm

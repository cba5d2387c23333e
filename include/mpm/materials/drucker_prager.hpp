#pragma once
/// Drucker-Prager plasticity with non-associated flow, a tension cut-off and a return to the apex
/// (de Souza Neto et al. 2008, Sec. 8.3), its cone matched to Mohr-Coulomb's hexagonal pyramid.
///
/// Yield function f = sqrt(J2) + eta p - xi c, plastic potential g = sqrt(J2) + eta_bar p (tension positive,
/// p = tr(sigma) / 3), and the tension cut-off p <= t. The return works in the (p, sqrt(J2)) plane, where the
/// elastic stiffnesses are K and G and the deviator keeps its direction (de Souza Neto et al. 2008,
/// Sec. 8.3).
#include <limits>
#include <string>

#include "mpm/materials/frictional.hpp"

namespace mpm {

/// Which Mohr-Coulomb pyramid the cone goes through (de Souza Neto et al. 2008, Sec. 6.4): its outer edges
/// (triaxial compression), its inner edges (triaxial extension), or the plane-strain collapse stress.
enum class ConeMatch { outer, inner, plane_strain };

/// The cone's coefficients for friction angle phi: f = sqrt(J2) + eta p - xi c (the same formula with the
/// dilatancy angle gives eta_bar).
struct ConeCoefficients {
  Real eta, xi;
};
ConeCoefficients cone_coefficients(ConeMatch match, Real phi);

struct DruckerPrager : FrictionalSolid {
  ConeMatch match = ConeMatch::outer;
  /// t, the largest mean stress [Pa] (the tension cut-off); infinite: none, the cone's apex bounds p.
  Real tension = std::numeric_limits<Real>::infinity();
};

/// Check the material; throw InputError naming `where` and the key.
void validate(const DruckerPrager& m, const std::string& where);

/// A strength held fixed over a return, for one particle (T = Real) or lanes: the elastic moduli, the cone's
/// eta and xi c, the potential's eta_bar and t, the largest mean stress (the cut-off, or the apex xi c / eta
/// where it comes first).
template <class T>
struct ConeStrength {
  T G, K, eta, xi_c, eta_bar, t;
};

/// The strength of m at plastic strain e.
ConeStrength<Real> cone_strength(const DruckerPrager& m, Real e);

/// A Drucker-Prager material as the lanes read it: its strength (fixed unless it softens or hardens), its
/// lambda, and whether its strength changes with the plastic strain (1) or not (0).
struct DruckerPragerRow {
  ConeStrength<Real> cone;
  Real lambda;
  Real softens;
};

/// A trial stress against a fixed strength: its mean stress p, deviator s and sqrt(J2), and whether it lies
/// outside the cone (f = sqrt(J2) + eta p - xi c > 0, de Souza Neto et al. 2008, Sec. 8.3) or beyond the
/// cut-off.
template <class T>
struct ConeTrial {
  T p, tau, f;
  Sym3<T> dev;
  simd::MaskOf<T> plastic;
};

template <class T>
[[gnu::always_inline]] inline ConeTrial<T> cone_trial(const ConeStrength<T>& s, const Sym3<T>& trial) {
  ConeTrial<T> c;
  c.p = trace(trial) / 3;
  c.dev = deviator(trial);
  c.tau = simd::sqrt(0.5 * contract(c.dev, c.dev));  // sqrt(J2)
  c.f = c.tau + s.eta * c.p - s.xi_c;                // de Souza Neto et al. 2008, Sec. 8.3
  c.plastic = (c.f > 0) | (c.p > s.t);
  return c;
}

/// Return a trial stress outside a fixed strength to its surface: the cone, the cut-off, their corner or the
/// apex, whichever holds the backward-Euler stress (de Souza Neto et al. 2008, Sec. 8.3, perfectly plastic at
/// this strength). Branch-free, for one particle or lanes (where a lane inside the surface gets a stress to
/// be ignored).
template <class T>
[[gnu::always_inline]] inline Sym3<T> return_to_cone(const ConeStrength<T>& s, const ConeTrial<T>& c) {
  // The smooth cone: sqrt(J2) = tau_trial - G dgamma, p = p_trial - K eta_bar dgamma, f = 0.
  const T dgamma = c.f / (s.G + s.K * s.eta * s.eta_bar);
  const T tau_cone = c.tau - s.G * dgamma, p_cone = c.p - s.K * s.eta_bar * dgamma;
  const auto on_cone = (c.f > 0) & (tau_cone >= 0) & (p_cone <= s.t);
  // Otherwise the cut-off alone (p = t with the deviator kept) where that lies inside the cone, else the
  // corner of cone and cut-off (the apex when t is the apex): p = t, sqrt(J2) on the cone.
  const auto on_cut_off = (c.p > s.t) & (c.tau + s.eta * s.t - s.xi_c <= 0);
  const T corner = simd::max(T{}, s.xi_c - s.eta * s.t);
  const T p = on_cone ? p_cone : s.t;
  const T tau = on_cone ? tau_cone : on_cut_off ? c.tau : corner;
  const T scale = tau / c.tau;  // the deviator keeps its direction
  Sym3<T> sigma;
  for (int k = 0; k < 6; ++k) sigma.c[k] = c.tau > 0 ? scale * c.dev.c[k] : T{};
  for (int k = 0; k < 3; ++k) sigma.c[k] += p;
  return sigma;
}

/// Return a trial stress to the surface of the strength at plastic strain e (cone_trial, return_to_cone).
FrictionalReturn return_at_strength(const DruckerPrager& m, const Eigen::Matrix3d& trial, Real e);

/// One step from sigma_n and eps_bar_n with strain increment de and spin increment dW (de(2, 2) as given:
/// plane strain, the hoop strain or 3-D).
StressUpdate update_stress(const DruckerPrager& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                           const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW);

}  // namespace mpm

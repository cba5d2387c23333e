#pragma once
/// Hypoelastic linear elasticity with the Jaumann rate, and von Mises plasticity with the bilinear hardening
/// law of Sulsky & Kaul 2004, "Implicit dynamics in the material-point method", Secs 2.1.1, 2.2.4 and 2.3.
///
/// Every tensor is 3x3 whatever the dimension of the simulation: plane strain, plane stress and axisymmetric
/// motion all need the out-of-plane (zz, or hoop) component of stress and strain.
///
/// Equivalent plastic strain. Sulsky & Kaul 2004, Eq. (2.1.18) as printed reads eps_bar = int
/// (d eps_pl : d eps_pl)^{1/2} = sqrt(2/3) gamma, which is inconsistent with d eps_pl = d gamma N and |N| = 1
/// (Sulsky & Kaul 2004, Eq. (2.1.10), Eq. (2.1.15)): the first integral is gamma itself. We use the standard
/// definition eps_bar = sqrt(2/3) gamma, i.e. d eps_bar = (2/3 d eps_pl : d eps_pl)^{1/2}
/// (Simo & Hughes 1998, Box 3.2: alpha += sqrt(2/3) dgamma), so that eps_bar is the plastic strain of a
/// uniaxial test and the consistency condition reads q_trial - 3 mu d_eps_bar = H.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/state.hpp"
#include "mpm/materials/sym3.hpp"

namespace mpm {

using Mat3 = Eigen::Matrix3d;

/// Bilinear strength H(eps_bar) of Sulsky & Kaul 2004, Eq. (2.1.19): tau0 + c1 e for e <= e_L, then
/// tau_L - c2 (e - e_L), where e_L = (tau_L - tau0)/c1 is where the first line reaches the limit strength
/// tau_L; optionally floored at a residual strength.
struct HardeningLaw {
  Real yield = 0;      ///< tau0, initial strength [Pa]
  Real hardening = 0;  ///< c1, slope of the first segment [Pa]
  /// tau_L, limit strength [Pa] (infinity: the first segment never ends)
  Real limit = std::numeric_limits<Real>::infinity();
  Real softening = 0;  ///< c2, softening slope beyond the limit [Pa] (> 0 softens)
  Real residual = 0;   ///< floor: H never drops below this [Pa] (0 = no floor)

  /// e_L, the plastic strain at which the first segment reaches the limit strength (inf when it never does).
  Real limit_strain() const {
    if (!(limit < std::numeric_limits<Real>::infinity())) return std::numeric_limits<Real>::infinity();
    return (limit - yield) / hardening;
  }

  /// H(e), the strength at equivalent plastic strain e >= 0. Sulsky & Kaul 2004, Eq. (2.1.19), floored.
  /// The pieces are [0, e_L), [e_L, e_F) and [e_F, inf) (e_F = floor_strain()), the same as slope() and
  /// next_kink() use, so that a rounded kink position never puts them on different pieces.
  Real strength(Real e) const {
    if (e >= floor_strain()) return residual;
    const Real eL = limit_strain();
    // Sulsky & Kaul 2004, Eq. (2.1.19)
    const Real h = e < eL ? yield + hardening * e : limit - softening * (e - eL);
    return residual > 0 && h < residual ? residual : h;
  }

  /// dH/de at e (the right derivative, so at a kink it is the slope of the segment that starts there).
  Real slope(Real e) const {
    if (e >= floor_strain()) return 0;
    return e < limit_strain() ? hardening : -softening;
  }

  /// The smallest plastic strain > e at which H has a kink (the limit strain, or where H meets the residual
  /// floor); inf when none follows.
  Real next_kink(Real e) const {
    constexpr Real inf = std::numeric_limits<Real>::infinity();
    const Real eL = limit_strain();
    if (e < eL && eL < inf) return eL;
    const Real eF = floor_strain();
    return e < eF ? eF : inf;
  }

  /// The plastic strain at which the descending part of H reaches the residual floor (inf if never).
  Real floor_strain() const {
    constexpr Real inf = std::numeric_limits<Real>::infinity();
    if (!(residual > 0)) return inf;
    const Real eL = limit_strain();
    if (eL == inf) return hardening < 0 ? std::max<Real>(0, (yield - residual) / -hardening) : inf;
    return softening > 0 ? eL + std::max<Real>(0, (limit - residual) / softening) : inf;
  }

  /// The smallest H over e in [0, inf): if <= 0, H <= 0 is reachable (-inf when H decreases without bound).
  Real min_strength() const {
    constexpr Real inf = std::numeric_limits<Real>::infinity();
    const Real eL = limit_strain();
    Real m = yield;
    if (eL == inf) {
      if (hardening < 0) m = -inf;
    } else {
      m = std::min(m, limit);
      if (softening > 0) m = -inf;
    }
    return residual > 0 ? std::max(m, residual) : m;
  }
};

namespace detail {
[[noreturn]] inline void bad_input(const std::string& where, const char* key, const std::string& what) {
  throw InputError(where + "." + key + ": " + what);
}
inline std::string number(Real x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}
}  // namespace detail

/// Check a hardening law; throw InputError naming `where` and the offending key (yield_strength, hardening,
/// limit_strength, softening, residual_strength) if H is not a positive bilinear function of eps_bar.
inline void validate(const HardeningLaw& law, const std::string& where) {
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  using detail::bad_input;
  using detail::number;
  if (!(std::isfinite(law.yield) && law.yield > 0))
    bad_input(where, "yield_strength",
              "expected a positive initial strength tau0 [Pa], got " + number(law.yield));
  if (!std::isfinite(law.hardening)) bad_input(where, "hardening", "expected a finite slope c1 [Pa]");
  if (std::isnan(law.limit) || law.limit < law.yield)
    bad_input(where, "limit_strength",
              "the limit strength tau_L = " + number(law.limit) + " is below the initial strength tau0 = " +
                  number(law.yield) + " (Sulsky & Kaul 2004, Eq. (2.1.19))");
  if (law.limit < inf && !(law.hardening > 0))
    bad_input(where, "hardening",
              "a finite limit_strength needs a positive hardening slope c1 (the limit strain "
              "(tau_L - tau0)/c1 is undefined otherwise), got " +
                  number(law.hardening));
  if (!std::isfinite(law.softening)) bad_input(where, "softening", "expected a finite slope c2 [Pa]");
  if (!(std::isfinite(law.residual) && law.residual >= 0))
    bad_input(where, "residual_strength",
              "expected a residual strength >= 0 [Pa], got " + number(law.residual));
  if (law.residual > law.yield)
    bad_input(where, "residual_strength",
              "the residual strength " + number(law.residual) + " exceeds the initial strength tau0 = " +
                  number(law.yield) + " (it is a floor for softening)");
  if (!(law.min_strength() > 0)) {
    // Only a negative c1 with no limit can bring H down on the first segment.
    const bool first = law.limit == inf;
    const Real e0 = first ? law.yield / -law.hardening : law.limit_strain() + law.limit / law.softening;
    bad_input(where, first ? "hardening" : "softening",
              std::string("the strength H reaches zero at plastic strain ") + number(e0) +
                  "; give residual_strength > 0 or " + (first ? "hardening >= 0" : "softening = 0") +
                  " (Sulsky & Kaul 2004 assume H > 0)");
  }
}

/// Hypoelastic (plastic == false) or von Mises elastic-plastic material. Sulsky & Kaul 2004, Sec. 2.1.1.
struct ElastoPlastic {
  Real E = 0;              ///< Young's modulus [Pa]
  Real nu = 0;             ///< Poisson's ratio
  Real rho0 = 0;           ///< reference density [kg/m^3]
  Real specific_heat = 0;  ///< c [J/(kg K)] for the plastic heating of Sulsky & Kaul 2004, Eq. (2.3.5);
                           ///< 0: no heating
  /// false: linear hypoelastic (Sulsky & Kaul 2004, Eq. (2.1.8)); true: von Mises plasticity
  /// (Sulsky & Kaul 2004, Eq. (2.1.9) to Eq. (2.1.19))
  bool plastic = false;
  HardeningLaw law;  ///< H(eps_bar), used when plastic

  Real lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }  ///< first Lame constant [Pa]
  Real mu() const { return E / (2 * (1 + nu)); }                      ///< shear modulus [Pa]
  /// Dilatational wave speed sqrt((lambda + 2 mu)/rho) at current density rho [m/s].
  Real wave_speed(Real rho) const { return std::sqrt((lambda() + 2 * mu()) / rho); }
};

/// Check a material; throw InputError naming `where` and the key (E, nu, density, specific_heat, or a key of
/// the hardening law when plastic).
inline void validate(const ElastoPlastic& m, const std::string& where) {
  using detail::bad_input;
  using detail::number;
  if (!(std::isfinite(m.E) && m.E > 0))
    bad_input(where, "E", "expected a positive Young's modulus [Pa], got " + number(m.E));
  if (!(m.nu > -1 && m.nu < 0.5))
    bad_input(where, "nu", "expected a Poisson ratio in (-1, 0.5), got " + number(m.nu));
  if (!(std::isfinite(m.rho0) && m.rho0 > 0))
    bad_input(where, "density", "expected a positive density [kg/m^3], got " + number(m.rho0));
  if (!(std::isfinite(m.specific_heat) && m.specific_heat >= 0))
    bad_input(where, "specific_heat",
              "expected a specific heat >= 0 [J/(kg K)], got " + number(m.specific_heat));
  if (m.plastic) validate(m.law, where);
}

/// How the out-of-plane (index 2) component of the strain increment is treated.
enum class OutOfPlane {
  given,         ///< de(2,2) used as given: plane strain (0), axisymmetric hoop strain, or 3-D
  plane_stress,  ///< de(2,2) solved so that sigma(2,2) = 0
};

/// The result of one stress update.
struct StressUpdate {
  Mat3 sigma;                ///< Cauchy stress at the end of the step [Pa]
  Real eps_bar;              ///< equivalent plastic strain at the end (Sulsky & Kaul 2004, Eq. (2.1.18))
  Real plastic_work;         ///< sigma : d_eps_plastic per unit current volume [J/m^3] (Sulsky & Kaul 2004,
                             ///< Eq. (2.3.5) right-hand side)
  Real d_eps_zz;             ///< the out-of-plane strain increment used (solved in plane stress)
  bool plastic;              ///< whether the return map was active
  InternalState internal{};  ///< the law's internal variables at the end (those it declares; cam_clay.hpp)
};

/// Deviatoric part sigma - tr(sigma)/3 I. Sulsky & Kaul 2004, Eq. (2.1.17).
inline Mat3 deviator(const Mat3& sigma) {
  return sigma - (sigma.trace() / 3) * Mat3::Identity();  // Sulsky & Kaul 2004, Eq. (2.1.17)
}

/// Von Mises equivalent stress q = sqrt(3 J2), J2 = s : s / 2. Sulsky & Kaul 2004, Eq. (2.1.13),
/// Eq. (2.1.14).
inline Real von_mises(const Mat3& sigma) {
  return std::sqrt(1.5 * deviator(sigma).squaredNorm());  // Sulsky & Kaul 2004, Eq. (2.1.14): 3 J2 = 3/2 s:s
}

/// Temperature rise rho c dT = sigma : d eps_pl for a plastic work density w [J/m^3] at current density rho
/// [kg/m^3]; 0 when the material has no specific heat. Sulsky & Kaul 2004, Eq. (2.3.5).
inline Real temperature_increment(const ElastoPlastic& m, Real plastic_work, Real rho) {
  return m.specific_heat > 0 ? plastic_work / (rho * m.specific_heat) : 0;  // Sulsky & Kaul 2004, Eq. (2.3.5)
}

/// Rotation of the stress by the incremental spin dW (skew): the Hughes & Winget 1980 rotation of
/// rotate_jaumann on Sym3 (sym3.hpp), whose axial vector is that of dW / 2. sigma must be symmetric.
inline Mat3 rotate_jaumann(const Mat3& sigma, const Mat3& dW) {
  return full(rotate_jaumann(sym3_of(sigma), spin_of(dW)));
}

namespace detail {

/// Outcome of the return map applied to one trial stress.
struct Return {
  Mat3 sigma;      ///< stress after the return
  Real d_eps_bar;  ///< plastic multiplier increment (0 when elastic)
  Real q;          ///< von Mises stress after the return
  Real dszz_ddzz;  ///< d sigma_zz / d de_zz of the whole update (elastic or consistent tangent)
  bool plastic;
};

/// Backward-Euler radial return of a trial stress onto f = 3 J2 - H^2 = 0 (Sulsky & Kaul 2004, Eq. (2.1.13),
/// Eq. (2.1.14), Eq. (2.1.15), Eq. (2.1.16)); Simo & Hughes 1998, Box 3.2. Solves q_trial - 3 mu d =
/// H(eps_bar_n + d) exactly on the piecewise linear H by walking its segments. Also returns
/// d sigma_zz / d de_zz (used by the plane-stress solve).
[[gnu::always_inline]] inline Return radial_return(const ElastoPlastic& m, Real mu, Real lambda,
                                                   const Mat3& trial, Real eps_bar_n) {
  Return r;
  const Real p = trial.trace() / 3;
  Mat3 s = trial;
  s.diagonal().array() -= p;
  const Real q_trial = std::sqrt(1.5 * s.squaredNorm());  // Sulsky & Kaul 2004, Eq. (2.1.14)
  const Real H_n = m.plastic ? m.law.strength(eps_bar_n) : 0;
  if (!m.plastic || !(q_trial > H_n)) {  // f <= 0: elastic. Sulsky & Kaul 2004, Eq. (2.1.13)
    r.sigma = trial;
    r.d_eps_bar = 0;
    r.q = q_trial;
    r.dszz_ddzz = lambda + 2 * mu;
    r.plastic = false;
    return r;
  }
  // Find the segment of H where g(d) = q_trial - 3 mu d - H(eps_bar_n + d) changes sign (g(0) > 0), then
  // solve the linear equation on it. Simo & Hughes 1998, Box 3.2 (exact here since H is piecewise linear).
  // The segment start is tracked as the absolute strain e_a (not eps_bar_n + a, which can round to just below
  // a kink and stall the walk).
  const Real three_mu = 3 * mu;
  Real e_a = eps_bar_n, a = 0, H_a = H_n, k = 0;
  for (int seg = 0; seg < 4; ++seg) {
    k = m.law.slope(e_a);
    const Real e_b = m.law.next_kink(e_a);
    if (!(e_b < std::numeric_limits<Real>::infinity())) break;
    const Real b = e_b - eps_bar_n;
    const Real H_b = m.law.strength(e_b);
    if (q_trial - three_mu * b - H_b <= 0) break;  // the root lies in [a, b]
    e_a = e_b;
    a = b;
    H_a = H_b;
  }
  const Real d = a + (q_trial - three_mu * a - H_a) / (three_mu + k);  // q_trial - 3 mu d = H_a + k (d - a)
  const Real q = q_trial - three_mu * d;                               // = H(eps_bar_n + d)
  // s = s_trial - 2 mu sqrt(3/2) d N with N = s_trial/|s_trial| (Sulsky & Kaul 2004, Eq. (2.1.15),
  // Eq. (2.1.16)), i.e. s = (q / q_trial) s_trial.
  const Real ratio = q / q_trial;
  r.sigma = ratio * s;
  r.sigma.diagonal().array() += p;
  r.d_eps_bar = d;
  r.q = q;
  r.plastic = true;
  // Consistent tangent, zz-zz entry: d sigma_zz = kappa dz + d(ratio s_zz), with ds_zz = 4/3 mu dz,
  // dq_trial = 3 mu s_zz/q_trial dz, dq = k/(3 mu + k) dq_trial.
  const Real kappa = lambda + 2 * mu / 3;
  const Real dq_trial = three_mu * s(2, 2) / q_trial;
  const Real dratio = (k / (three_mu + k) - ratio) * dq_trial / q_trial;
  r.dszz_ddzz = kappa + ratio * (4 * mu / 3) + s(2, 2) * dratio;
  return r;
}

/// The elastic trial stress for out-of-plane increment z: base + lambda z I + 2 mu z e_z e_z, where base
/// holds the rotated stress plus the in-plane part of the increment. Sulsky & Kaul 2004, Eq. (2.2.21).
[[gnu::always_inline]] inline Mat3 trial_at(const Mat3& base, Real mu, Real lambda, Real z) {
  Mat3 t = base;
  t.diagonal().array() += lambda * z;
  t(2, 2) += 2 * mu * z;
  return t;
}

/// Plane stress: given the plastic return r at the elastic guess dz, find dz such that sigma_zz = 0 after the
/// return, trial(dz) = base + lambda dz I + 2 mu dz e_z e_z. Kept out of line so the common path stays small.
[[gnu::noinline]] inline void solve_plane_stress(const ElastoPlastic& m, Real mu, Real lambda,
                                                 const Mat3& base, Real eps_bar_n, Return& r, Real& dz) {
  // Solve sigma_zz(dz) = 0: Newton with the consistent tangent (quadratic convergence), safeguarded by
  // bisection once a sign change is bracketed (the map is piecewise smooth: kinks where the return switches
  // segment or turns elastic). Stop at |sigma_zz| <= 1e-14 scale, or once |sigma_zz| <= 1e-12 scale after one
  // more (polishing) step, keeping the better of the two; the guarantee is |sigma_zz| <= 1e-12 scale.
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  constexpr Real tight = 1e-14, loose = 1e-12;
  Real lo = -inf, hi = inf;  // sigma_zz(lo) < 0 < sigma_zz(hi) (sigma_zz increases with dz)
  bool polished = false, done = false;
  Return r_best = r;
  Real dz_best = dz, f_best = inf;
  for (int it = 0; it < 100; ++it) {
    const Real f = r.sigma(2, 2);
    const Real scale = std::max(r.sigma.cwiseAbs().maxCoeff(), m.law.strength(eps_bar_n + r.d_eps_bar));
    if (std::abs(f) / scale < f_best) {
      f_best = std::abs(f) / scale;
      r_best = r;
      dz_best = dz;
    }
    if (f_best <= tight || (polished && f_best <= loose)) {
      done = true;
      break;
    }
    polished = f_best <= loose;
    if (f < 0)
      lo = std::max(lo, dz);
    else
      hi = std::min(hi, dz);
    Real next = dz - f / r.dszz_ddzz;
    if (!(r.dszz_ddzz > 0) || !(next > lo && next < hi) || !std::isfinite(next)) {
      if (lo > -inf && hi < inf) {
        next = 0.5 * (lo + hi);
      } else {  // no bracket yet and Newton unusable: step by the elastic stiffness
        next = dz - f / (lambda + 2 * mu);
      }
    }
    if (next == dz) break;  // no representable progress
    dz = next;
    r = radial_return(m, mu, lambda, trial_at(base, mu, lambda, dz), eps_bar_n);
  }
  if (!done && !(f_best <= loose))
    throw SimulationFailure(
        std::string("elastoplastic update: the plane-stress solve for sigma_zz = 0 did not converge") +
        (m.law.softening >= 3 * mu ? " (the softening slope is >= 3 mu, so the stress can jump with strain)"
                                   : ""));
  r = r_best;
  dz = dz_best;
}

}  // namespace detail

/// One step of the rate-form update. Rotate sigma_n with the spin increment dW (skew, = dt skew(grad v)) by
/// the Hughes & Winget 1980 rotation (the Jaumann rate, Sulsky & Kaul 2004 Sec. 2.2.4), add the elastic trial
/// increment lambda tr(de) I + 2 mu de (Sulsky & Kaul 2004, Eq. (2.2.17), Eq. (2.2.21)) and, if plastic and
/// 3 J2 > H^2 (Sulsky & Kaul 2004, Eq. (2.1.13)), return to the yield surface by backward Euler
/// (Sulsky & Kaul 2004, Eq. (2.1.15), Eq. (2.1.16); Simo & Hughes 1998, Box 3.2). de must be symmetric;
/// de(2,2) is used as given unless mode is plane_stress, where it is solved so that sigma(2,2) = 0 (to 1e-12
/// max(|sigma|, H), typically 1e-14). Throws SimulationFailure if that solve fails.
inline StressUpdate update_stress(const ElastoPlastic& m, const Mat3& sigma_n, Real eps_bar_n, const Mat3& de,
                                  const Mat3& dW, OutOfPlane mode) {
  const Real mu = m.mu(), lambda = m.lambda();
  // Objective rotation of the old stress. Hughes & Winget 1980; Sulsky & Kaul 2004, Sec. 2.2.4.
  const Mat3 sigma_rot = rotate_jaumann(sigma_n, dW);

  // Elastic trial stress with de(2,2) taken as 0: sigma + lambda tr(de) I + 2 mu de. Sulsky & Kaul 2004,
  // Eq. (2.2.17), Eq. (2.2.21) with T = E, the isotropic elasticity tensor.
  Real dz = mode == OutOfPlane::given ? de(2, 2) : 0;
  const Real tr_in = de(0, 0) + de(1, 1);
  Mat3 base = sigma_rot + 2 * mu * de;
  base(2, 2) = sigma_rot(2, 2);
  base.diagonal().array() += lambda * tr_in;

  if (mode == OutOfPlane::plane_stress) dz = -base(2, 2) / (lambda + 2 * mu);  // closed form when elastic
  detail::Return r = detail::radial_return(m, mu, lambda, detail::trial_at(base, mu, lambda, dz), eps_bar_n);

  if (mode == OutOfPlane::plane_stress && r.plastic)
    detail::solve_plane_stress(m, mu, lambda, base, eps_bar_n, r, dz);

  StressUpdate out;
  out.sigma = r.sigma;
  out.eps_bar = eps_bar_n + r.d_eps_bar;
  // sigma : d eps_pl = s : (sqrt(3/2) d N) = q d, since s = sqrt(2/3) q N. Sulsky & Kaul 2004, Eq. (2.3.5).
  out.plastic_work = r.q * r.d_eps_bar;
  out.d_eps_zz = dz;
  out.plastic = r.plastic;
  return out;
}

}  // namespace mpm

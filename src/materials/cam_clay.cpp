// Modified Cam-Clay's return in the invariants p' and q: Borja & Lee 1990, with the exponential volumetric
// laws of Butterfield 1979 integrated exactly over the step.
#include "mpm/materials/cam_clay.hpp"

#include <algorithm>
#include <cmath>

#include "mpm/core/errors.hpp"

namespace mpm {

// A number in messages, and the "where.KEY: what" error of the laws' checks (elastoplastic.hpp).
using detail::bad_input;
using detail::number;

InternalState ModifiedCamClay::initial_state(const SymTensor<3>& sigma, const InternalState& given) const {
  const bool from_file = !std::isnan(given[0]);
  const Real pc = from_file ? given[0] : pc0;
  if (from_file && !(std::isfinite(pc) && pc > 0))
    throw InputError("preconsolidation_pressure: expected a positive pressure [Pa], got " + number(pc));
  const Eigen::Matrix3d s = sigma.full();
  const Real p = 0.0 - s.trace() / 3, q = von_mises(s);  // 0 - 0 = +0 (a stress-free particle reads "p' = 0")
  if (!(p > 0))
    throw InputError(
        "a particle of this modified-cam-clay material starts at mean effective stress p' = " + number(p) +
        " Pa; the model has no strength without confinement: start the body in compression "
        "(k0 under gravity)");
  if (q * q / (M * M) + p * (p - pc) > 1e-12 * pc * pc)  // Roscoe & Burland 1968: f <= 0
    throw InputError("a particle of this modified-cam-clay material starts outside its yield surface (p' = " +
                     number(p) + " Pa, q = " + number(q) + " Pa, preconsolidation_pressure " + number(pc) +
                     " Pa): raise preconsolidation_pressure" + (from_file ? " in the particle file" : ""));
  return {pc};
}

void validate(const ModifiedCamClay& m, const std::string& where, Geometry geometry) {
  const auto positive = [&](Real v, const char* key, const char* what) {
    if (!(std::isfinite(v) && v > 0))
      bad_input(where, key, std::string("expected ") + what + ", got " + number(v));
  };
  positive(m.rho0, "density", "a positive density [kg/m^3]");
  positive(m.M, "M", "a positive slope of the critical state line");
  positive(m.kappa_star, "swelling_index",
           "a positive slope kappa* of the swelling line (ln v against ln p')");
  positive(m.lambda_star, "compression_index", "a positive slope lambda* of the normal compression line");
  if (!(m.lambda_star > m.kappa_star))
    bad_input(where, "compression_index",
              "the normal compression line must be steeper than the swelling line (lambda* = " +
                  number(m.lambda_star) + " > kappa* = " + number(m.kappa_star) + ")");
  if (std::isnan(m.nu) == std::isnan(m.G))
    bad_input(where, std::isnan(m.nu) ? "nu" : "shear_modulus",
              "give exactly one of nu (a constant Poisson ratio) and shear_modulus (a constant G)");
  if (!std::isnan(m.nu) && !(m.nu > -1 && m.nu < 0.5))
    bad_input(where, "nu", "expected a Poisson ratio in (-1, 0.5), got " + number(m.nu));
  if (!std::isnan(m.G)) positive(m.G, "shear_modulus", "a positive shear modulus [Pa]");
  positive(m.pc0, "preconsolidation_pressure",
           "a positive preconsolidation pressure [Pa] (compression positive)");
  if (geometry == Geometry::plane_stress)
    bad_input(where, "model", "modified Cam-Clay runs in plane strain, axisymmetry or 3-D, not plane stress");
}

StressUpdate update_stress(const ModifiedCamClay& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                           const InternalState& internal_n, const Eigen::Matrix3d& de,
                           const Eigen::Matrix3d& dW) {
  // The elastic trial: the rotated stress (Hughes & Winget 1980; Sulsky & Kaul 2004, Sec. 2.2.4), its mean
  // effective stress on the swelling line p' = p'_n exp(d eps_v / kappa*) (Butterfield 1979) and its deviator
  // s_n + 2 G dev(de) (Sulsky & Kaul 2004, Eq. (2.2.21)).
  const Eigen::Matrix3d rotated = rotate_jaumann(sigma_n, dW);
  const Real p_n = -rotated.trace() / 3, pc_n = internal_n[0];
  if (!(p_n > 0) || !(pc_n > 0))
    throw SimulationFailure("modified Cam-Clay: a particle's mean effective stress p' = " + number(p_n) +
                            " Pa or preconsolidation pressure " + number(pc_n) +
                            " Pa is not positive (the model has no tensile strength)");
  const Real G = m.shear_at(p_n), ks = m.kappa_star, plastic_slope = m.lambda_star - m.kappa_star,
             M2 = m.M * m.M;
  const Real d_ev = -de.trace();  // compression positive
  const Real p_trial = p_n * std::exp(d_ev / ks);
  const Eigen::Matrix3d s_trial = deviator(rotated) + 2 * G * deviator(de);
  const Real q_trial = std::sqrt(1.5 * s_trial.squaredNorm());
  StressUpdate out;
  out.d_eps_zz = de(2, 2);
  // Roscoe & Burland 1968: f = q^2 / M^2 + p' (p' - p_c).
  if (q_trial * q_trial / M2 + p_trial * (p_trial - pc_n) <= 0) {
    out.sigma = s_trial - p_trial * Eigen::Matrix3d::Identity();
    out.eps_bar = eps_bar_n;
    out.plastic_work = 0;
    out.plastic = false;
    out.internal = internal_n;
    return out;
  }
  // Backward Euler (Borja & Lee 1990) in the unknowns y = ln p' and dgamma, with associated flow:
  //   d eps_v^p = dgamma df/dp' = dgamma (2 p' - p_c),   d eps_q^p = dgamma df/dq = dgamma 2 q / M^2;
  //   p' = p'_trial exp(-d eps_v^p / kappa*),           p_c = p_c,n exp(d eps_v^p / (lambda* - kappa*));
  //   q = q_trial / (1 + 6 G dgamma / M^2) (3 G d eps_q^p taken off the trial, the deviator keeping its
  //   direction); R1 = d eps_v^p - dgamma (2 p' - p_c) = 0,         R2 = f(p', q, p_c) / p_c,n^2 = 0.
  const Real c = 6 * G / M2, ln_p_trial = std::log(p_trial);
  Real y = ln_p_trial, dgamma = 0, p = p_trial, pc = pc_n, q = q_trial, x = 0;
  const auto evaluate = [&] {
    p = std::exp(y);
    x = ks * (ln_p_trial - y);
    pc = pc_n * std::exp(x / plastic_slope);
    q = q_trial / (1 + c * dgamma);
  };
  // Converged when both residuals are at the round-off of their terms: R1 against kappa* (the scale of x), R2
  // against 1.
  bool converged = false;
  for (int it = 0; it < 60; ++it) {
    const Real R1 = x - dgamma * (2 * p - pc);
    const Real R2 = (q * q / M2 + p * (p - pc)) / (pc_n * pc_n);
    if (std::abs(R1) <= 1e-14 * ks && std::abs(R2) <= 1e-14) {
      converged = true;
      break;
    }
    const Real J11 = -ks - dgamma * (2 * p + pc * ks / plastic_slope), J12 = -(2 * p - pc);
    const Real J21 = (2 * p * p - p * pc + p * pc * ks / plastic_slope) / (pc_n * pc_n);
    const Real J22 = -2 * q * q * c / (M2 * (1 + c * dgamma)) / (pc_n * pc_n);
    const Real det = J11 * J22 - J12 * J21;
    if (!(std::abs(det) > 0)) break;
    Real dy = -(J22 * R1 - J12 * R2) / det, dg = -(-J21 * R1 + J11 * R2) / det;
    // Damped: p' changes by at most a factor e per iteration, and dgamma stays >= 0.
    const Real damp = std::min<Real>(1, 1 / std::max<Real>(std::abs(dy), 1e-300));
    dy *= damp, dg *= damp;
    if (dgamma + dg < 0) dg = -0.5 * dgamma;
    y += dy, dgamma += dg;
    evaluate();
  }
  if (!converged || !std::isfinite(p))
    throw SimulationFailure(
        "modified Cam-Clay: the return to the yield surface did not converge (p'_trial = " + number(p_trial) +
        " Pa, q_trial = " + number(q_trial) + " Pa, p_c = " + number(pc_n) + " Pa)");
  out.sigma = (q_trial > 0 ? q / q_trial : 0) * s_trial - p * Eigen::Matrix3d::Identity();
  const Real d_eq = dgamma * 2 * q / M2;
  out.eps_bar = eps_bar_n + d_eq;
  out.plastic_work = p * x + q * d_eq;  // sigma : d eps^p = p' d eps_v^p + q d eps_q^p
  out.plastic = true;
  out.internal = {pc};
  return out;
}

}  // namespace mpm

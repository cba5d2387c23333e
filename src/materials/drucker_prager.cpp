// Drucker-Prager's return in the (p, sqrt(J2)) plane: de Souza Neto et al. 2008, Sec. 8.3, with a tension
// cut-off.
#include "mpm/materials/drucker_prager.hpp"

#include <algorithm>
#include <cmath>

#include "mpm/materials/elastoplastic.hpp"

namespace mpm {

namespace {
ConeCoefficients compute_cone(ConeMatch match, Real phi) {
  const Real s = std::sin(phi), c = std::cos(phi), root3 = std::sqrt(3.0);
  switch (match) {
    case ConeMatch::outer:  // de Souza Neto et al. 2008, Sec. 6.4: through the compressive edges
      return {6 * s / (root3 * (3 - s)), 6 * c / (root3 * (3 - s))};
    case ConeMatch::inner:  // de Souza Neto et al. 2008, Sec. 6.4: through the tensile edges
      return {6 * s / (root3 * (3 + s)), 6 * c / (root3 * (3 + s))};
    case ConeMatch::plane_strain: {  // de Souza Neto et al. 2008, Sec. 6.4: Mohr-Coulomb's plane-strain
                                     // collapse
      const Real t = std::tan(phi), d = std::sqrt(9 + 12 * t * t);
      return {3 * t / d, 3 / d};
    }
  }
  return {0, 0};
}
}  // namespace

ConeCoefficients cone_coefficients(ConeMatch match, Real phi) {
  // The last two angles each thread asked for (the friction and the dilatancy angle of the material it is
  // updating): their trigonometry is most of an elastic step's cost otherwise. The same bits either way.
  struct Entry {
    ConeMatch match;
    Real phi;
    ConeCoefficients cone;
  };
  thread_local Entry memo[2] = {{ConeMatch::outer, -1, {}}, {ConeMatch::outer, -1, {}}};
  thread_local int next = 0;
  for (const Entry& e : memo)
    if (e.phi == phi && e.match == match) return e.cone;
  memo[next] = {match, phi, compute_cone(match, phi)};
  const ConeCoefficients out = memo[next].cone;
  next ^= 1;
  return out;
}

void validate(const DruckerPrager& m, const std::string& where) {
  validate(static_cast<const FrictionalSolid&>(m), where);
  if (!(m.tension >= 0))
    detail::bad_input(where, "tension_cutoff",
                      "expected a largest mean stress >= 0 [Pa], got " + detail::number(m.tension));
}

ConeStrength<Real> cone_strength(const DruckerPrager& m, Real e) {
  const Real c = m.strength.cohesion_at(e);
  const ConeCoefficients cone = cone_coefficients(m.match, m.strength.friction_at(e));
  const Real t = cone.eta > 0 ? std::min(m.tension, cone.xi * c / cone.eta) : m.tension;
  return {m.mu(), m.bulk(), cone.eta, cone.xi * c, cone_coefficients(m.match, m.strength.dilatancy).eta, t};
}

FrictionalReturn return_at_strength(const DruckerPrager& m, const Eigen::Matrix3d& trial, Real e) {
  const ConeStrength<Real> strength = cone_strength(m, e);
  const ConeTrial<Real> c = cone_trial(strength, sym3_of(trial));
  if (!c.plastic) return {trial, false};
  return {full(return_to_cone(strength, c)), true};
}

StressUpdate update_stress(const DruckerPrager& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                           const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW) {
  return return_with_softening(
      m, frictional_trial(m, sigma_n, de, dW), eps_bar_n, de(2, 2),
      [&m](const Eigen::Matrix3d& trial, Real e) { return return_at_strength(m, trial, e); });
}

}  // namespace mpm

// What the frictional plasticity models share: validation, the trial stress and the plastic strain and work
// of a return.
#include "mpm/materials/frictional.hpp"

#include <numbers>

#include "mpm/materials/elastoplastic.hpp"

namespace mpm {

namespace {
std::string degrees(Real rad) {
  return detail::number(rad * 180 / std::numbers::pi) + " degrees";
}
}  // namespace

void validate(const FrictionalStrength& s, const std::string& where) {
  using detail::bad_input;
  using detail::number;
  const Real right = std::numbers::pi / 2;
  if (!(std::isfinite(s.cohesion) && s.cohesion >= 0))
    bad_input(where, "cohesion", "expected a cohesion >= 0 [Pa], got " + number(s.cohesion));
  if (!(s.friction >= 0 && s.friction < right))
    bad_input(where, "friction_angle", "expected an angle in [0, 90) degrees, got " + degrees(s.friction));
  if (!(s.cohesion > 0 || s.friction > 0))
    bad_input(where, "cohesion", "a material with no cohesion and no friction angle has no strength");
  if (!(std::isfinite(s.residual_strain) && s.residual_strain >= 0))
    bad_input(where, "residual_strain", "expected a plastic strain >= 0, got " + number(s.residual_strain));
  if (s.constant() && (s.residual_cohesion != s.cohesion || s.residual_friction != s.friction))
    bad_input(where, "residual_strain",
              "a residual cohesion or friction angle needs the plastic strain at which it is reached (> 0)");
  if (!(std::isfinite(s.residual_cohesion) && s.residual_cohesion >= 0))
    bad_input(where, "residual_cohesion",
              "expected a cohesion >= 0 [Pa], got " + number(s.residual_cohesion));
  if (!(s.residual_friction >= 0 && s.residual_friction < right))
    bad_input(where, "residual_friction_angle",
              "expected an angle in [0, 90) degrees, got " + degrees(s.residual_friction));
  if (!(s.residual_cohesion > 0 || s.residual_friction > 0))
    bad_input(where, "residual_cohesion", "the residual strength has no cohesion and no friction angle");
  const Real phi_min = std::min(s.friction, s.residual_friction);
  if (!(s.dilatancy >= 0 && s.dilatancy <= phi_min))
    bad_input(where, "dilatancy_angle",
              "expected an angle in [0, " + degrees(phi_min) + "] (at most the friction angle), got " +
                  degrees(s.dilatancy));
}

void validate(const FrictionalSolid& m, const std::string& where) {
  using detail::bad_input;
  using detail::number;
  if (!(std::isfinite(m.E) && m.E > 0))
    bad_input(where, "E", "expected a positive Young's modulus [Pa], got " + number(m.E));
  if (!(m.nu > -1 && m.nu < 0.5))
    bad_input(where, "nu", "expected a Poisson ratio in (-1, 0.5), got " + number(m.nu));
  if (!(std::isfinite(m.rho0) && m.rho0 > 0))
    bad_input(where, "density", "expected a positive density [kg/m^3], got " + number(m.rho0));
  validate(m.strength, where);
}

Real plastic_work_density(const Eigen::Matrix3d& trial, const Eigen::Matrix3d& sigma, Real K, Real G) {
  const Real p = sigma.trace() / 3, p_trial = trial.trace() / 3;
  const Eigen::Matrix3d s = deviator(sigma);
  return p * (p_trial - p) / K + s.cwiseProduct(deviator(trial) - s).sum() / (2 * G);
}

Eigen::Matrix3d frictional_trial(const FrictionalSolid& m, const Eigen::Matrix3d& sigma_n,
                                 const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW) {
  return full(hypoelastic_trial(sym3_of(sigma_n), StrainIncrement<Real>{sym3_of(de), spin_of(dW)}, m.mu(),
                                m.lambda()));
}

}  // namespace mpm

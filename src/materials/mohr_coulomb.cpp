// Mohr-Coulomb's multi-surface return in principal stresses: de Souza Neto et al. 2008, Sec. 8.2.
#include "mpm/materials/mohr_coulomb.hpp"

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

namespace mpm {

namespace {

using Principal = Eigen::Vector3d;  // s1 >= s2 >= s3

/// The plane (i, j), i < j, of the pyramid in the ordered sector: f = s_i - s_j + (s_i + s_j) sin(phi) - 2 c
/// cos(phi) (de Souza Neto et al. 2008, Sec. 8.2), its gradient a and the elastic image D n of its flow
/// direction n = (1 + sin(psi)) e_i - (1 - sin(psi)) e_j, D n = lambda tr(n) 1 + 2 G n.
struct Plane {
  int i, j;
  Real f(const Principal& s, Real sin_phi, Real c_cos_phi) const {
    return s[i] - s[j] + (s[i] + s[j]) * sin_phi - 2 * c_cos_phi;
  }
  Principal gradient(Real sin_phi) const {
    Principal a = Principal::Zero();
    a[i] = 1 + sin_phi;
    a[j] = -(1 - sin_phi);
    return a;
  }
  Principal elastic_flow(Real sin_psi, Real lambda, Real G) const {
    Principal dn = Principal::Constant(lambda * 2 * sin_psi);
    dn[i] += 2 * G * (1 + sin_psi);
    dn[j] -= 2 * G * (1 - sin_psi);
    return dn;
  }
};

constexpr Plane main_plane{0, 2}, right_plane{0, 1}, left_plane{1, 2};

}  // namespace

void validate(const MohrCoulomb& m, const std::string& where) {
  validate(static_cast<const FrictionalSolid&>(m), where);
}

FrictionalReturn return_at_strength(const MohrCoulomb& m, const Eigen::Matrix3d& trial, Real e) {
  const Real G = m.mu(), lambda = m.lambda();
  const Real phi = m.strength.friction_at(e), c = m.strength.cohesion_at(e);
  const Real sin_phi = std::sin(phi), c_cos_phi = c * std::cos(phi), sin_psi = std::sin(m.strength.dilatancy);
  // Elastic without the principal stresses when a bound of f is: s1 - s3 <= 2 sqrt(J2) and s1 + s3 = 2 p -
  // s2'
  // <= 2 p + 2 sqrt(J2 / 3), s2' the middle principal deviator (|s'_k| <= 2 sqrt(J2 / 3)).
  const Real p = trial.trace() / 3, root_J2 = std::sqrt(0.5 * deviator(trial).squaredNorm());
  if (2 * root_J2 + (2 * p + 2 * root_J2 / std::sqrt(3.0)) * sin_phi - 2 * c_cos_phi <= 0)
    return {trial, false};
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(trial);
  const Principal trial_s = eigen.eigenvalues().reverse();  // Eigen's are ascending
  const auto stress = [&](const Principal& s) {
    return FrictionalReturn{
        eigen.eigenvectors() * s.reverse().asDiagonal() * eigen.eigenvectors().transpose(), true};
  };
  const Real f_trial = main_plane.f(trial_s, sin_phi, c_cos_phi);
  if (f_trial <= 0) return {trial, false};

  // One plane: sigma = trial - dgamma D n, with a . D n dgamma = f_trial (de Souza Neto et al. 2008,
  // Sec. 8.2).
  const Principal dn_main = main_plane.elastic_flow(sin_psi, lambda, G);
  const Principal on_main = trial_s - f_trial / main_plane.gradient(sin_phi).dot(dn_main) * dn_main;
  if (on_main[0] >= on_main[1] && on_main[1] >= on_main[2]) return stress(on_main);

  // An edge: the main plane and the one whose ordering the single return broke (de Souza Neto et al. 2008,
  // Sec. 8.2), two multipliers from the 2 x 2 system A dgamma = f_trial, A_kl = a_k . D n_l.
  const bool right = on_main[1] < on_main[2];
  const Plane& other = right ? right_plane : left_plane;
  const Principal dn_other = other.elastic_flow(sin_psi, lambda, G);
  const Principal a_main = main_plane.gradient(sin_phi), a_other = other.gradient(sin_phi);
  Eigen::Matrix2d A;
  A << a_main.dot(dn_main), a_main.dot(dn_other), a_other.dot(dn_main), a_other.dot(dn_other);
  const Eigen::Vector2d dgamma = A.inverse() * Eigen::Vector2d(f_trial, other.f(trial_s, sin_phi, c_cos_phi));
  const Principal on_edge = trial_s - dgamma[0] * dn_main - dgamma[1] * dn_other;
  const bool ordered = right ? on_edge[0] >= on_edge[1] : on_edge[1] >= on_edge[2];
  if (ordered || !(sin_phi > 0)) return stress(on_edge);

  // The apex: every principal stress c cot(phi) (de Souza Neto et al. 2008, Sec. 8.2).
  return stress(Principal::Constant(c_cos_phi / sin_phi));
}

StressUpdate update_stress(const MohrCoulomb& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                           const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW) {
  return return_with_softening(
      m, frictional_trial(m, sigma_n, de, dW), eps_bar_n, de(2, 2),
      [&m](const Eigen::Matrix3d& trial, Real e) { return return_at_strength(m, trial, e); });
}

}  // namespace mpm

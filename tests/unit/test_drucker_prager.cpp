// Drucker-Prager plasticity (de Souza Neto et al. 2008, Sec. 8.3) driven through strain paths at one material
// point: the cones matched to Mohr-Coulomb, triaxial compression, simple shear, tension against the cut-off
// and the apex, the dilatancy of the flow, softening, the tangent of tiny steps and the surface after huge
// ones. Tolerances: a stress after a return is exact up to the round-off of a few operations on stresses of
// the size of the state, so yield functions are asserted to 1e-12 of that size.
#include <random>

#include "frictional_paths.hpp"

namespace {

using namespace frictional_paths;
using mpm::ConeMatch;
using mpm::DruckerPrager;

DruckerPrager dp(ConeMatch match = ConeMatch::outer) {
  DruckerPrager m = soil<DruckerPrager>();
  m.match = match;
  return m;
}

Real sqrt_j2(const Mat3& s) {
  return std::sqrt(0.5 * mpm::deviator(s).squaredNorm());
}

/// f = sqrt(J2) + eta p - xi c at plastic strain e, computed here from the definition.
Real yield(const DruckerPrager& m, const Mat3& sigma, Real e) {
  const mpm::ConeCoefficients cone = mpm::cone_coefficients(m.match, m.strength.friction_at(e));
  return sqrt_j2(sigma) + cone.eta * sigma.trace() / 3 - cone.xi * m.strength.cohesion_at(e);
}

TEST(DruckerPrager, OuterAndInnerConesPassThroughMohrCoulombsEdges) {
  const Real phi = 30 * degree, c = 10e3, s = std::sin(phi), cs = c * std::cos(phi);
  for (Real sr : {0.0, -50e3, -400e3}) {
    // Triaxial compression (s1 = s2 = sr > s3) and extension (s1 > s2 = s3 = sr) on Mohr-Coulomb's pyramid:
    // s1 - s3 + (s1 + s3) sin(phi) = 2 c cos(phi).
    const Real s3 = (sr * (1 + s) - 2 * cs) / (1 - s), s1 = (2 * cs + sr * (1 - s)) / (1 + s);
    EXPECT_NEAR(yield(dp(ConeMatch::outer), diagonal(sr, sr, s3), 0), 0, 1e-12 * std::abs(s3));
    EXPECT_NEAR(yield(dp(ConeMatch::inner), diagonal(s1, sr, sr), 0), 0, 1e-12 * std::abs(s1 - sr));
  }
}

TEST(DruckerPrager, PlaneStrainConeGivesMohrCoulombsPlaneStrainStrength) {
  // Associated flow with no plastic strain out of the plane: dev(sigma)_zz = -2 eta sqrt(J2) / 3. With
  // in-plane principal stresses p_in +- R, R = c cos(phi) - p_in sin(phi) (Mohr-Coulomb), d = p_in - p and J2
  // = R^2 + 3 d^2, so sqrt(J2) = R / sqrt(1 - eta^2 / 3) and the stress must lie on the plane-strain cone.
  const DruckerPrager m = dp(ConeMatch::plane_strain);
  const Real phi = m.strength.friction, c = m.strength.cohesion;
  const Real eta = mpm::cone_coefficients(ConeMatch::plane_strain, phi).eta;
  for (Real p_in : {0.0, -50e3, -400e3}) {
    const Real R = c * std::cos(phi) - p_in * std::sin(phi);
    const Real tau = R / std::sqrt(1 - eta * eta / 3), d = tau * eta / 3;
    const Mat3 sigma = diagonal(p_in + R, p_in - R, p_in - 3 * d);
    EXPECT_NEAR(sqrt_j2(sigma), tau, 1e-12 * tau);
    EXPECT_NEAR(yield(m, sigma, 0), 0, 1e-12 * tau);
  }
}

TEST(DruckerPrager, TriaxialCompressionReachesTheConesAxialStress) {
  // On the cone with s = diag(sr, sr, sa): (sr - sa)/sqrt(3) + eta (2 sr + sa)/3 = xi c.
  const DruckerPrager m = dp();
  const mpm::ConeCoefficients cone = mpm::cone_coefficients(m.match, m.strength.friction);
  const Real sr = -100e3;
  const Real sa = (cone.xi * m.strength.cohesion - sr * (1 / std::sqrt(3.0) + 2 * cone.eta / 3)) /
                  (cone.eta / 3 - 1 / std::sqrt(3.0));
  const StressUpdate u = triaxial(m, sr, -0.05, 500);
  EXPECT_NEAR(u.sigma(2, 2), sa, 1e-10 * std::abs(sa));
  EXPECT_NEAR(u.sigma(0, 0), sr, 1e-10 * std::abs(sr));
  EXPECT_GT(u.eps_bar, 0.01);
}

TEST(DruckerPrager, FlowDilatesAsTheDilatancyAngleSays) {
  // de_p = dgamma (dev(sigma) / (2 sqrt(J2)) + eta_bar / 3 I): tr(de_p) = eta_bar dgamma and d eps_bar =
  // dgamma / sqrt(3), so tr(de_p) / d eps_bar = sqrt(3) eta_bar; its deviator is parallel to dev(sigma).
  for (Real psi : {0.0, 10.0, 30.0}) {
    DruckerPrager m = dp();
    m.strength.dilatancy = psi * degree;
    const Mat3 sigma_n = diagonal(-100e3, -100e3, -100e3), de = diagonal(0.01, 0.01, -0.02);
    const StressUpdate u = step(m, sigma_n, 0, de);
    ASSERT_TRUE(u.plastic);
    const Mat3 ep = plastic_strain(m, sigma_n, u.sigma, de);
    const Real eta_bar = mpm::cone_coefficients(m.match, m.strength.dilatancy).eta;
    EXPECT_NEAR(ep.trace() / u.eps_bar, std::sqrt(3.0) * eta_bar, 1e-9) << "psi = " << psi;
    const Mat3 e_dev = mpm::deviator(ep), s = mpm::deviator(u.sigma);
    EXPECT_NEAR(e_dev.cwiseProduct(s).sum(), e_dev.norm() * s.norm(), 1e-9 * e_dev.norm() * s.norm());
  }
}

TEST(DruckerPrager, SimpleShearAtConstantVolumeSaturatesAtTheConesShearStress) {
  // With psi = 0 neither the mean stress nor the shear direction changes: sqrt(J2) = tau_xy = xi c - eta p0.
  DruckerPrager m = dp(ConeMatch::plane_strain);
  m.strength.dilatancy = 0;
  const Real p0 = -100e3;
  const StressUpdate u = simple_shear(m, diagonal(p0, p0, p0), 0.1, 200);
  const mpm::ConeCoefficients cone = mpm::cone_coefficients(m.match, m.strength.friction);
  EXPECT_NEAR(u.sigma(0, 1), cone.xi * m.strength.cohesion - cone.eta * p0, 1e-10 * std::abs(p0));
  EXPECT_NEAR(u.sigma.trace() / 3, p0, 1e-10 * std::abs(p0));
}

TEST(DruckerPrager, TensionEndsAtTheCutOffOrTheApex) {
  // Isotropic extension from zero stress: no deviator, so the mean stress stops at the cut-off t or, without
  // one, at the apex xi c / eta = c cot(phi) (outer cone), and no deviatoric plastic strain accumulates.
  DruckerPrager m = dp();
  const Real apex = m.strength.cohesion / std::tan(m.strength.friction);
  StressUpdate u = step(m, Mat3::Zero(), 0, diagonal(0.01, 0.01, 0.01));
  EXPECT_NEAR((u.sigma - diagonal(apex, apex, apex)).norm(), 0, 1e-10 * apex);
  EXPECT_EQ(u.eps_bar, 0);
  m.tension = 5e3;
  u = step(m, Mat3::Zero(), 0, diagonal(0.01, 0.01, 0.01));
  EXPECT_NEAR((u.sigma - diagonal(5e3, 5e3, 5e3)).norm(), 0, 1e-10 * apex);
  // Pure (uniaxial-strain) tension: the mean stress reaches t and the stress stays inside the cone.
  u = step(m, diagonal(-10e3, -10e3, -10e3), 0, diagonal(0.02, 0, 0));
  EXPECT_NEAR(u.sigma.trace() / 3, 5e3, 1e-10 * apex);
  EXPECT_LE(yield(m, u.sigma, u.eps_bar), 1e-12 * apex);
}

TEST(DruckerPrager, SofteningCohesionFollowsThePlasticStrain) {
  // Simple shear at constant volume (psi = 0): after every plastic step the stress lies on the cone of the
  // reported eps_bar, and once the residual strength is reached tau_xy stays xi c_r - eta p0 while eps_bar
  // grows by the plastic shear strain over sqrt(3).
  DruckerPrager m = dp(ConeMatch::plane_strain);
  m.strength.dilatancy = 0;
  m.strength.residual_cohesion = 2e3;
  m.strength.residual_friction = 25 * degree;
  m.strength.residual_strain = 0.05;
  const Real p0 = -100e3, dgamma = 1e-3;
  StressUpdate u{diagonal(p0, p0, p0), 0, 0, 0, false};
  Mat3 de = Mat3::Zero();
  de(0, 1) = de(1, 0) = 0.5 * dgamma;
  Real eps_before = 0;
  for (int k = 0; k < 300; ++k) {
    eps_before = u.eps_bar;
    u = step(m, u.sigma, u.eps_bar, de);
    if (u.plastic) {
      ASSERT_NEAR(yield(m, u.sigma, u.eps_bar), 0, 1e-12 * std::abs(p0)) << "step " << k;
    }
  }
  const mpm::ConeCoefficients cone = mpm::cone_coefficients(m.match, m.strength.residual_friction);
  EXPECT_NEAR(u.sigma(0, 1), cone.xi * 2e3 - cone.eta * p0, 1e-10 * std::abs(p0));
  EXPECT_GT(eps_before, m.strength.residual_strain);
  EXPECT_NEAR(u.eps_bar - eps_before, dgamma / std::sqrt(3.0), 1e-12);
}

TEST(DruckerPrager, TinyStepsFollowTheContinuumTangentToSecondOrder) {
  // From a state on the cone, d sigma = D de - D n (a : D de) / (G + K eta eta_bar) with a and n the
  // gradients of f and g (perfect plasticity); backward Euler differs by O(|de|^2).
  const DruckerPrager m = dp();
  const StressUpdate on = triaxial(m, -100e3, -0.02, 200);
  const Real G = m.mu(), K = m.bulk();
  const mpm::ConeCoefficients cone = mpm::cone_coefficients(m.match, m.strength.friction);
  const Real eta_bar = mpm::cone_coefficients(m.match, m.strength.dilatancy).eta;
  const Mat3 s = mpm::deviator(on.sigma);
  const Real tau = sqrt_j2(on.sigma);
  const Mat3 a = s / (2 * tau) + cone.eta / 3 * Mat3::Identity(),
             Dn = G / tau * s + K * eta_bar * Mat3::Identity();
  Mat3 direction;
  direction << 0.1, 0.3, 0.05, 0.3, 0.2, -0.1, 0.05, -0.1, -1.0;
  expect_second_order_tangent(m, on, a, Dn, direction);
}

TEST(DruckerPrager, EveryStepEndsOnOrInsideTheSurfaceFromTinyToHugeIncrements) {
  // The returns land on the cone, on the cut-off, at their corner and at the apex; each is counted.
  std::mt19937 gen(7);
  int cone_only = 0, cutoff_only = 0, corner = 0, apex = 0;
  std::uniform_real_distribution<Real> unit(-1, 1);
  for (const bool soften : {false, true})
    for (const Real t : {std::numeric_limits<Real>::infinity(), 3e3}) {
      DruckerPrager m = soil<DruckerPrager>(soften);
      m.tension = t;
      for (int k = 0; k < 400; ++k) {
        const Real size = std::pow(10.0, -9 + 9 * (k % 10) / 9.0);
        // Every other step starts near the cut-off and adds an extension, so that some end on it alone.
        const bool near_cutoff = k % 2;
        Mat3 de, sigma_n = near_cutoff ? diagonal(2e3, 2e3, 2.5e3) : diagonal(-100e3, -60e3, -20e3);
        for (int i = 0; i < 3; ++i)
          for (int j = i; j < 3; ++j) de(i, j) = de(j, i) = size * unit(gen);
        if (near_cutoff) de.diagonal().array() += 2 * size;
        const StressUpdate u = step(m, sigma_n, 0.002 * (k % 3), de);
        const Real scale = std::max(u.sigma.cwiseAbs().maxCoeff(), m.strength.cohesion);
        ASSERT_TRUE(u.sigma.allFinite());
        EXPECT_LE(yield(m, u.sigma, u.eps_bar), 1e-12 * scale) << "size " << size;
        EXPECT_LE(u.sigma.trace() / 3, t + 1e-12 * scale);
        if (u.plastic) {
          const bool on_cone = std::abs(yield(m, u.sigma, u.eps_bar)) <= 1e-12 * scale;
          const bool on_cutoff = std::abs(u.sigma.trace() / 3 - t) <= 1e-12 * scale;
          EXPECT_TRUE(on_cone || on_cutoff) << "size " << size;
          const bool tip = sqrt_j2(u.sigma) <= 1e-12 * scale;
          (tip ? apex : on_cone && on_cutoff ? corner : on_cone ? cone_only : cutoff_only)++;
        }
      }
    }
  EXPECT_GT(cone_only, 10);
  EXPECT_GT(cutoff_only, 10);
  EXPECT_GT(corner, 10);
  EXPECT_GT(apex, 10);
}

TEST(DruckerPrager, InvalidParametersAreRefusedAtTheirKey) {
  const auto refused = [](const DruckerPrager& m, const std::string& key) {
    try {
      mpm::validate(mpm::Material{m}, "materials[0]", 2, mpm::Geometry::plane_strain);
    } catch (const mpm::InputError& e) {
      return std::string(e.what()).find("materials[0]." + key + ":") == 0;
    }
    return false;
  };
  DruckerPrager m = dp();
  m.strength.cohesion = m.strength.residual_cohesion = -1;
  EXPECT_TRUE(refused(m, "cohesion"));
  m = dp();
  m.strength.friction = m.strength.residual_friction = 90 * degree;
  EXPECT_TRUE(refused(m, "friction_angle"));
  m = dp();
  m.strength.dilatancy = 31 * degree;
  EXPECT_TRUE(refused(m, "dilatancy_angle"));
  m = dp();
  m.strength.residual_cohesion = 1e3;
  EXPECT_TRUE(refused(m, "residual_strain"));
  m = dp();
  m.tension = -1;
  EXPECT_TRUE(refused(m, "tension_cutoff"));
  m = dp();
  m.strength.cohesion = m.strength.residual_cohesion = 0;
  m.strength.friction = m.strength.residual_friction = 0;
  m.strength.dilatancy = 0;
  EXPECT_TRUE(refused(m, "cohesion"));
  EXPECT_THROW(mpm::validate(mpm::Material{dp()}, "materials[0]", 2, mpm::Geometry::plane_stress),
               mpm::InputError);
}

}  // namespace

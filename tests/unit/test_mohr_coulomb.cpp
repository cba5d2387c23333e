// Mohr-Coulomb plasticity (de Souza Neto et al. 2008, Sec. 8.2) driven through strain paths at one material
// point: triaxial compression and extension (the edge returns), simple shear, tension to the apex, the
// dilatancy of the flow, softening of cohesion and friction angle, the tangent of tiny steps and the surface
// after huge ones. Tolerances: a stress after a return is exact up to the round-off of a few operations (and
// of the eigen-decomposition) on stresses of the size of the state: yield functions are asserted to 1e-12 of
// it.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <random>

#include "frictional_paths.hpp"

namespace {

using namespace frictional_paths;
using mpm::MohrCoulomb;

/// The principal stresses, largest first.
Eigen::Vector3d principal(const Mat3& sigma) {
  return Eigen::SelfAdjointEigenSolver<Mat3>(sigma).eigenvalues().reverse();
}

/// f = s1 - s3 + (s1 + s3) sin(phi) - 2 c cos(phi) at plastic strain e.
Real yield(const MohrCoulomb& m, const Mat3& sigma, Real e) {
  const Eigen::Vector3d s = principal(sigma);
  const Real phi = m.strength.friction_at(e);
  return s[0] - s[2] + (s[0] + s[2]) * std::sin(phi) - 2 * m.strength.cohesion_at(e) * std::cos(phi);
}

TEST(MohrCoulomb, TriaxialCompressionReachesTheClosedFormOnTheEdge) {
  // s1 = s2 = sr > s3: the left edge, where s3 = (sr (1 + sin(phi)) - 2 c cos(phi)) / (1 - sin(phi)).
  const MohrCoulomb m = soil<MohrCoulomb>();
  const Real phi = m.strength.friction, c = m.strength.cohesion, sr = -100e3;
  const Real sa = (sr * (1 + std::sin(phi)) - 2 * c * std::cos(phi)) / (1 - std::sin(phi));
  const StressUpdate u = triaxial(m, sr, -0.05, 500);
  EXPECT_NEAR(u.sigma(2, 2), sa, 1e-10 * std::abs(sa));
  EXPECT_NEAR(u.sigma(1, 1), sr, 1e-10 * std::abs(sr));
  EXPECT_GT(u.eps_bar, 0.01);
}

TEST(MohrCoulomb, TriaxialExtensionReachesTheClosedFormOnTheOtherEdge) {
  // s1 > s2 = s3 = sr: the right edge, where s1 = (2 c cos(phi) + sr (1 - sin(phi))) / (1 + sin(phi)).
  const MohrCoulomb m = soil<MohrCoulomb>();
  const Real phi = m.strength.friction, c = m.strength.cohesion, sr = -100e3;
  const Real sa = (2 * c * std::cos(phi) + sr * (1 - std::sin(phi))) / (1 + std::sin(phi));
  const StressUpdate u = triaxial(m, sr, 0.05, 500);
  EXPECT_NEAR(u.sigma(2, 2), sa, 1e-10 * std::abs(sr));
  EXPECT_NEAR(u.sigma(1, 1), sr, 1e-10 * std::abs(sr));
}

TEST(MohrCoulomb, FlowOnTheMainPlaneDilatesAsTheDilatancyAngleSays) {
  // de_p = dgamma ((1 + sin(psi)) e1 e1 - (1 - sin(psi)) e3 e3): (e1 + e3) / (e1 - e3) = sin(psi), e2 = 0.
  for (Real psi : {0.0, 10.0, 30.0}) {
    MohrCoulomb m = soil<MohrCoulomb>();
    m.strength.dilatancy = psi * degree;
    const Mat3 sigma_n = diagonal(-50e3, -100e3, -200e3), de = diagonal(0.004, 0.0005, -0.01);
    const StressUpdate u = step(m, sigma_n, 0, de);
    const Eigen::Vector3d s = principal(u.sigma);
    ASSERT_TRUE(u.plastic);
    ASSERT_GT(s[0] - s[1], 1e3);  // the main plane, away from the edges
    ASSERT_GT(s[1] - s[2], 1e3);
    const Eigen::Vector3d ep = plastic_strain(m, sigma_n, u.sigma, de).diagonal();
    EXPECT_NEAR((ep[0] + ep[2]) / (ep[0] - ep[2]), std::sin(m.strength.dilatancy), 1e-9) << "psi = " << psi;
    EXPECT_NEAR(ep[1], 0, 1e-12);
  }
}

TEST(MohrCoulomb, SimpleShearAtConstantVolumeSaturatesAtCohesionAndFriction) {
  // psi = 0: s = p0 I + tau (e_x e_y + e_y e_x) with s1, s3 = p0 +- tau and the Mohr-Coulomb surface gives
  // tau = c cos(phi) - p0 sin(phi).
  MohrCoulomb m = soil<MohrCoulomb>();
  m.strength.dilatancy = 0;
  const Real p0 = -100e3;
  const StressUpdate u = simple_shear(m, diagonal(p0, p0, p0), 0.1, 200);
  const Real phi = m.strength.friction;
  EXPECT_NEAR(u.sigma(0, 1), m.strength.cohesion * std::cos(phi) - p0 * std::sin(phi), 1e-10 * std::abs(p0));
  EXPECT_NEAR(u.sigma.trace() / 3, p0, 1e-10 * std::abs(p0));
}

TEST(MohrCoulomb, TensionEndsAtTheApex) {
  // Isotropic and uniaxial extension end at the apex c cot(phi) I.
  const MohrCoulomb m = soil<MohrCoulomb>();
  const Real apex = m.strength.cohesion / std::tan(m.strength.friction);
  for (const Mat3& de : {diagonal(0.01, 0.01, 0.01), diagonal(0.05, 0, 0)}) {
    const StressUpdate u = step(m, diagonal(-10e3, -10e3, -10e3), 0, de);
    EXPECT_NEAR((u.sigma - diagonal(apex, apex, apex)).norm(), 0, 1e-10 * apex);
  }
}

TEST(MohrCoulomb, SofteningOfCohesionAndFrictionFollowsThePlasticStrain) {
  // Simple shear at constant volume: on the surface of the reported eps_bar after every plastic step; at the
  // residual strength tau = c_r cos(phi_r) - p0 sin(phi_r).
  MohrCoulomb m = soil<MohrCoulomb>();
  m.strength.dilatancy = 0;
  m.strength.residual_cohesion = 2e3;
  m.strength.residual_friction = 25 * degree;
  m.strength.residual_strain = 0.05;
  const Real p0 = -100e3;
  StressUpdate u{diagonal(p0, p0, p0), 0, 0, 0, false};
  Mat3 de = Mat3::Zero();
  de(0, 1) = de(1, 0) = 0.5e-3;
  for (int k = 0; k < 300; ++k) {
    u = step(m, u.sigma, u.eps_bar, de);
    if (u.plastic) {
      ASSERT_NEAR(yield(m, u.sigma, u.eps_bar), 0, 1e-12 * std::abs(p0)) << "step " << k;
    }
  }
  const Real phi_r = m.strength.residual_friction;
  EXPECT_GT(u.eps_bar, m.strength.residual_strain);
  EXPECT_NEAR(u.sigma(0, 1), 2e3 * std::cos(phi_r) - p0 * std::sin(phi_r), 1e-10 * std::abs(p0));
}

TEST(MohrCoulomb, TinyStepsFollowTheContinuumTangentToSecondOrder) {
  // On the main plane, d sigma = D de - D n (a : D de) / (a : D n), a and n in the current principal frame;
  // the step rotates the frame (de has shear), so backward Euler differs by O(|de|^2).
  const MohrCoulomb m = soil<MohrCoulomb>();
  const StressUpdate on = step(m, diagonal(-50e3, -100e3, -200e3), 0, diagonal(0.004, 0.0005, -0.01));
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(on.sigma);
  const Eigen::Vector3d v1 = eigen.eigenvectors().col(2), v3 = eigen.eigenvectors().col(0);
  const Real sp = std::sin(m.strength.friction), sq = std::sin(m.strength.dilatancy), G = m.mu();
  const Mat3 a = (1 + sp) * v1 * v1.transpose() - (1 - sp) * v3 * v3.transpose();
  const Mat3 n = (1 + sq) * v1 * v1.transpose() - (1 - sq) * v3 * v3.transpose();
  Mat3 Dn = 2 * G * n;
  Dn.diagonal().array() += m.lambda() * n.trace();
  Mat3 direction;
  direction << 0.3, 0.2, 0.05, 0.2, 0.1, -0.1, 0.05, -0.1, -1.0;
  expect_second_order_tangent(m, on, a, Dn, direction);
}

TEST(MohrCoulomb, EveryStepEndsOnOrInsideTheSurfaceFromTinyToHugeIncrements) {
  // The returns land on the main plane, on both edges and at the apex; each is counted.
  std::mt19937 gen(11);
  int main_plane = 0, edge = 0, apex = 0;
  std::uniform_real_distribution<Real> unit(-1, 1);
  for (const bool soften : {false, true}) {
    const MohrCoulomb m = soil<MohrCoulomb>(soften);
    for (int k = 0; k < 400; ++k) {
      const Real size = std::pow(10.0, -9 + 9 * (k % 10) / 9.0);
      Mat3 de;
      for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) de(i, j) = de(j, i) = size * unit(gen);
      const StressUpdate u = step(m, diagonal(-100e3, -60e3, -20e3), 0.002 * (k % 3), de);
      const Real scale = std::max(u.sigma.cwiseAbs().maxCoeff(), m.strength.cohesion);
      ASSERT_TRUE(u.sigma.allFinite());
      EXPECT_LE(yield(m, u.sigma, u.eps_bar), 1e-12 * scale) << "size " << size;
      if (!u.plastic) continue;
      EXPECT_NEAR(yield(m, u.sigma, u.eps_bar), 0, 1e-12 * scale) << "size " << size;
      const Eigen::Vector3d s = principal(u.sigma);
      const bool left = s[0] - s[1] <= 1e-9 * scale, right = s[1] - s[2] <= 1e-9 * scale;
      (left && right ? apex : left || right ? edge : main_plane)++;
    }
  }
  EXPECT_GT(main_plane, 10);
  EXPECT_GT(edge, 10);
  EXPECT_GT(apex, 10);
}

}  // namespace

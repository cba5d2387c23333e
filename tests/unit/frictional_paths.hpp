// Strain paths that drive one material point of a frictional material (Drucker-Prager, Mohr-Coulomb), shared
// by their unit tests.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mpm/materials/material.hpp"

namespace frictional_paths {

using mpm::Mat3;
using mpm::Real;
using mpm::StressUpdate;

constexpr Real degree = std::numbers::pi / 180;

/// A soil: E = 20 MPa, nu = 0.3, c = 10 kPa, phi = 30 degrees, psi = 10 degrees.
template <class Law>
Law soil() {
  Law m;
  m.E = 20e6;
  m.nu = 0.3;
  m.rho0 = 2000;
  m.strength.cohesion = m.strength.residual_cohesion = 10e3;
  m.strength.friction = m.strength.residual_friction = 30 * degree;
  m.strength.dilatancy = 10 * degree;
  return m;
}

inline Mat3 diagonal(Real a, Real b, Real c) {
  return Eigen::Vector3d(a, b, c).asDiagonal();
}

/// The soil, or with `soften` a soil whose cohesion falls to 1 kPa and friction angle to 20 degrees at a
/// plastic strain of 0.01.
template <class Law>
Law soil(bool soften) {
  Law m = soil<Law>();
  if (soften) {
    m.strength.residual_cohesion = 1e3;
    m.strength.residual_friction = 20 * degree;
    m.strength.residual_strain = 0.01;
  }
  return m;
}

/// A step without spin.
template <class Law>
StressUpdate step(const Law& m, const Mat3& sigma, Real eps_bar, const Mat3& de) {
  return mpm::update_stress(m, sigma, eps_bar, de, Mat3::Zero());
}

/// The plastic strain increment of a step: de - C^-1 (sigma - sigma_n).
template <class Law>
Mat3 plastic_strain(const Law& m, const Mat3& sigma_n, const Mat3& sigma, const Mat3& de) {
  const Mat3 ds = sigma - sigma_n;
  Mat3 elastic = ds / (2 * m.mu());
  elastic.diagonal().array() -= m.lambda() * ds.trace() / (2 * m.mu() * (3 * m.lambda() + 2 * m.mu()));
  return de - elastic;
}

/// Drained triaxial test: from the isotropic stress sigma_r, the axial (zz) strain changes by axial / steps
/// per step while the lateral stresses stay sigma_r (the equal lateral strains solved by the secant method to
/// 1e-12 of sigma_r at each step).
template <class Law>
StressUpdate triaxial(const Law& m, Real sigma_r, Real axial, int steps) {
  StressUpdate u{diagonal(sigma_r, sigma_r, sigma_r), 0, 0, 0, false};
  const Real da = axial / steps;
  Real x_guess = -m.lambda() * da / (2 * m.lambda() + 2 * m.mu());  // elastic
  for (int k = 0; k < steps; ++k) {
    const auto at = [&](Real x) { return step(m, u.sigma, u.eps_bar, diagonal(x, x, da)); };
    Real x0 = x_guess, x1 = 1.01 * x_guess + 1e-12;
    StressUpdate u0 = at(x0), u1 = at(x1);
    for (int it = 0; it < 100 && std::abs(u1.sigma(0, 0) - sigma_r) > 1e-12 * std::abs(sigma_r); ++it) {
      const Real g0 = u0.sigma(0, 0) - sigma_r, g1 = u1.sigma(0, 0) - sigma_r;
      const Real x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
      x0 = x1, u0 = u1, x1 = x2, u1 = at(x2);
    }
    EXPECT_LE(std::abs(u1.sigma(0, 0) - sigma_r), 1e-12 * std::abs(sigma_r)) << "lateral solve at step " << k;
    x_guess = x1;
    u = u1;
  }
  return u;
}

/// Simple shear at constant volume: the engineering shear strain gamma_xy grows by gamma / steps per step
/// from the stress sigma_0.
template <class Law>
StressUpdate simple_shear(const Law& m, const Mat3& sigma_0, Real gamma, int steps) {
  StressUpdate u{sigma_0, 0, 0, 0, false};
  Mat3 de = Mat3::Zero();
  de(0, 1) = de(1, 0) = 0.5 * gamma / steps;
  for (int k = 0; k < steps; ++k) u = step(m, u.sigma, u.eps_bar, de);
  return u;
}

/// From the state `on` (on the surface, away from edges), steps of h * direction for h = 1e-5 and 1e-6
/// against the continuum tangent D de - D n (a : D de) / (a : D n), a and n the gradients of the yield
/// function and the plastic potential at `on` (perfect plasticity): the error is below 1e-3 |D de| and falls
/// by at least 50 for h / 10 (backward Euler differs by O(|de|^2)).
template <class Law>
void expect_second_order_tangent(const Law& m, const StressUpdate& on, const Mat3& a, const Mat3& Dn,
                                 const Mat3& direction) {
  Real previous = 0;
  for (Real h : {1e-5, 1e-6}) {
    const Mat3 de = h * direction;
    Mat3 D_de = 2 * m.mu() * de;
    D_de.diagonal().array() += m.lambda() * de.trace();
    const Real loading = a.cwiseProduct(D_de).sum();
    ASSERT_GT(loading, 0);
    const Mat3 expected = D_de - Dn * loading / a.cwiseProduct(Dn).sum();
    const Real error = (step(m, on.sigma, on.eps_bar, de).sigma - on.sigma - expected).norm();
    EXPECT_LT(error, 1e-3 * D_de.norm()) << "h = " << h;
    if (previous > 0) {
      EXPECT_GT(previous / error, 50) << "second order: error / 100 for h / 10";
    }
    previous = error;
  }
}

}  // namespace frictional_paths

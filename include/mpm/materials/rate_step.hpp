#pragma once
/// One particle's rate-form stress update over a step, shared by the explicit and implicit engines.
#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/elastoplastic.hpp"

namespace mpm {

/// A Dim x Dim tensor in the upper-left of a 3 x 3 one.
template <int Dim>
Mat3 embed(const Mat<Dim>& m) {
  Mat3 out = Mat3::Zero();
  out.template topLeftCorner<Dim, Dim>() = m;
  return out;
}

/// The packed form of a symmetric 3 x 3 tensor.
inline SymTensor<3> packed(const Mat3& m) {
  SymTensor<3> s;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) s(a, b) = m(a, b);
  return s;
}

/// The state of a particle at the end of a step.
struct RateStep {
  SymTensor<3> sigma;  ///< Cauchy stress [Pa]
  Real eps_bar;        ///< equivalent plastic strain
  Real work;           ///< plastic work of the step [J, per unit thickness or radian]
  Real energy;         ///< internal energy increment of the step [J, per unit thickness or radian]
  Real stretch3;       ///< out-of-plane stretch
  bool ok;             ///< J > 0, a positive out-of-plane stretch and a finite stress
};

/// Advance a particle of volume V over a step whose velocity-gradient increment is dL = dt grad v and whose hoop
/// strain increment (axisymmetric) is dt v_r / r. Strain and spin increments: Sulsky & Kaul 2004,
/// Eqs (2.2.18)-(2.2.20); the stress: update_stress; the internal energy with the mid-step stress: Sulsky & Kaul
/// 2004, Eq. (2.2.16).
template <int Dim>
RateStep rate_form_step(const ElastoPlastic& mat, const SymTensor<3>& sigma, Real eps_bar, Real stretch3, Real V,
                        const Mat<Dim>& dL, Real hoop_increment, Geometry geometry) {
  const Mat3 dL3 = embed<Dim>(dL);
  Mat3 de = 0.5 * (dL3 + dL3.transpose());
  const Mat3 dW = 0.5 * (dL3 - dL3.transpose());
  if (geometry == Geometry::axisymmetric) de(2, 2) = hoop_increment;
  const OutOfPlane mode = geometry == Geometry::plane_stress ? OutOfPlane::plane_stress : OutOfPlane::given;
  const Mat3 sigma_n = sigma.full();
  const StressUpdate u = update_stress(mat, sigma_n, eps_bar, de, dW, mode);
  de(2, 2) = u.d_eps_zz;
  RateStep out;
  out.stretch3 = geometry == Geometry::plane_strain ? 1.0 : stretch3 * (1 + de(2, 2));
  const Real J = (Mat<Dim>::Identity() + dL).determinant() * out.stretch3 / stretch3;
  out.ok = J > 0 && out.stretch3 > 0 && u.sigma.allFinite();
  out.sigma = packed(u.sigma);
  out.eps_bar = u.eps_bar;
  out.work = u.plastic_work * V;
  out.energy = V * (0.5 * (sigma_n + u.sigma)).cwiseProduct(de).sum();  // Sulsky & Kaul 2004, Eq. (2.2.16)
  return out;
}

}  // namespace mpm

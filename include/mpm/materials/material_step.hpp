#pragma once
/// One particle's stress update over a step for any material, shared by the explicit and implicit engines.
#include <cmath>
#include <type_traits>
#include <variant>

#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/materials/sym3.hpp"

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
struct MaterialStep {
  SymTensor<3> sigma;  ///< Cauchy stress [Pa]
  Real eps_bar;        ///< equivalent plastic strain
  Real work;           ///< plastic work of the step [J, per unit thickness or radian]
  Real energy;    ///< internal (or stored) energy increment of the step [J, per unit thickness or radian]
  Real stretch3;  ///< out-of-plane stretch
  InternalState internal;  ///< the law's internal variables (those it declares; zero for the others)
  bool ok;                 ///< J > 0, a positive out-of-plane stretch and a finite stress
};

/// Advance a particle of a rate-form solid (ElastoPlastic, DruckerPrager, MohrCoulomb, ModifiedCamClay) of
/// volume V over a step whose velocity-gradient increment is dL = dt grad v and whose hoop strain increment
/// (axisymmetric) is dt v_r / r. Strain and spin increments: Sulsky & Kaul 2004, Eq. (2.2.18), Eq. (2.2.19),
/// Eq. (2.2.20); the stress: update_stress (with the internal variables of the laws that declare them); the
/// internal energy with the mid-step stress: Sulsky & Kaul 2004, Eq. (2.2.16).
template <int Dim, class Law>
MaterialStep rate_form_step(const Law& mat, const SymTensor<3>& sigma, Real eps_bar, Real stretch3, Real V,
                            const Mat<Dim>& dL, Real hoop_increment, Geometry geometry,
                            const InternalState& internal = {}) {
  const Mat3 dL3 = embed<Dim>(dL);
  Mat3 de = 0.5 * (dL3 + dL3.transpose());
  const Mat3 dW = 0.5 * (dL3 - dL3.transpose());
  if (geometry == Geometry::axisymmetric) de(2, 2) = hoop_increment;
  const OutOfPlane mode = geometry == Geometry::plane_stress ? OutOfPlane::plane_stress : OutOfPlane::given;
  const Mat3 sigma_n = sigma.full();
  StressUpdate u;
  if constexpr (std::is_same_v<Law, ElastoPlastic>)
    u = update_stress(mat, sigma_n, eps_bar, de, dW, mode);
  else if constexpr (requires { Law::state_columns; })
    u = update_stress(mat, sigma_n, eps_bar, internal, de, dW);
  else
    u = update_stress(mat, sigma_n, eps_bar, de, dW);  // frictional: de(2, 2) as given (no plane stress)
  de(2, 2) = u.d_eps_zz;
  MaterialStep out{};
  out.stretch3 = geometry == Geometry::plane_strain ? 1.0 : stretch3 * (1 + de(2, 2));
  const Real J = (Mat<Dim>::Identity() + dL).determinant() * out.stretch3 / stretch3;
  out.ok = J > 0 && out.stretch3 > 0 && u.sigma.allFinite();
  out.sigma = packed(u.sigma);
  out.eps_bar = u.eps_bar;
  out.internal = u.internal;
  out.work = u.plastic_work * V;
  out.energy = V * mid_step_work(sym3_of(sigma_n), sym3_of(u.sigma), sym3_of(de));
  return out;
}

/// The Neo-Hookean Cauchy stress with its out-of-plane components: Wallstedt & Guilkey 2008, Eq. (55) in the
/// plane, lambda ln J / J out of it (plane strain in 2-D, uniaxial strain in 1-D).
template <int Dim>
SymTensor<3> neo_hookean_stress(const NeoHookean& law, const SymTensor<Dim>& in_plane, Real J) {
  SymTensor<3> s;
  for (int a = 0; a < 3; ++a)
    for (int c = a; c < 3; ++c)
      s(a, c) = a < Dim && c < Dim ? in_plane(a, c) : a == c ? law.lambda * std::log(J) / J : 0.0;
  return s;
}

/// A Neo-Hookean particle of reference volume V0 and deformation gradient F over a step with dL = dt grad v:
/// F_new = (I + dL) F (Wallstedt & Guilkey 2008, Eq. (11)), the stress of Eq. (55), and the change of the
/// stored energy V0 W(F).
template <int Dim>
MaterialStep hyperelastic_step(const NeoHookean& law, const Mat<Dim>& F, Real V0, const Mat<Dim>& dL) {
  const Mat<Dim> F_new = (Mat<Dim>::Identity() + dL) * F;
  const Real J = F_new.determinant();
  MaterialStep out{};
  out.stretch3 = 1;
  out.ok = J > 0 && std::isfinite(J);
  if (!out.ok) return out;
  out.sigma = neo_hookean_stress<Dim>(law, law.template stress<Dim>(F_new, J), J);
  out.energy = V0 * (law.template energy_density<Dim>(F_new, J) -
                     law.template energy_density<Dim>(F, F.determinant()));
  out.ok = out.sigma.full().allFinite();
  return out;
}

/// A Newtonian fluid particle of volume V and deformation gradient F over a step dt with dL = dt grad v: the
/// stress of Sulsky & Kaul 2004, Eq. (2.1.7) at the end of the step (J of F_new = (I + dL) F, the rate dL /
/// dt), and the internal energy with the mid-step stress (Sulsky & Kaul 2004, Eq. (2.2.16)), which takes in
/// the dissipation.
template <int Dim>
MaterialStep fluid_step(const NewtonianFluid& law, const SymTensor<3>& sigma, Real V, const Mat<Dim>& F,
                        const Mat<Dim>& dL, Real dt) {
  const Real J = ((Mat<Dim>::Identity() + dL) * F).determinant();
  const Mat3 de = embed<Dim>(0.5 * (dL + dL.transpose()));
  const Mat3 s = law.stress(de / dt, J);
  MaterialStep out{};
  out.stretch3 = 1;
  out.sigma = packed(s);
  out.energy = V * mid_step_work(sym3_of(sigma.full()), sym3_of(s), sym3_of(de));
  out.ok = J > 0 && s.allFinite();
  return out;
}

/// One particle over a step dt, whatever its material: hyperelastic_step, rate_form_step or fluid_step.
template <int Dim>
MaterialStep material_step(const Material& material, const SymTensor<3>& sigma, Real eps_bar, Real stretch3,
                           const InternalState& internal, Real V, Real V0, const Mat<Dim>& F,
                           const Mat<Dim>& dL, Real dt, Real hoop_increment, Geometry geometry) {
  return std::visit(
      [&](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (std::is_same_v<Law, NeoHookean>)
          return hyperelastic_step<Dim>(law, F, V0, dL);
        else if constexpr (std::is_same_v<Law, NewtonianFluid>)
          return fluid_step<Dim>(law, sigma, V, F, dL, dt);
        else
          return rate_form_step<Dim>(law, sigma, eps_bar, stretch3, V, dL, hoop_increment, geometry,
                                     internal);
      },
      material);
}

}  // namespace mpm

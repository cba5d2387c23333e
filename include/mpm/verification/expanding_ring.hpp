#pragma once
/// Manufactured solution: radial expansion of a ring (Wallstedt & Guilkey 2008, Sec. 5.2, Eq. (60), Eq. (61),
/// Eq. (62)), with the Neo-Hookean of Eq. (54) at zero Poisson ratio, P = mu F^{-1}(F F^T - I). By symmetry
/// the quarter ring X, Y >= 0 is modelled, with symmetry planes at X = 0 and Y = 0.
#include <cmath>
#include <numbers>

#include "mpm/core/types.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {

struct ExpandingRing {
  static constexpr int dim = 2;
  Real A;          ///< displacement of the outer surface, A = u(R_O) [m]
  NeoHookean mat;  ///< lambda = 0, mu = E/2
  Real R_I = 0.5;  ///< inner radius [m]
  Real R_O = 1.0;  ///< outer radius [m]

  Real young() const { return 2 * mat.mu; }
  Real c() const { return std::sqrt(young() / mat.rho0); }  ///< c^2 = E / rho0
  Real omega() const { return c() * std::numbers::pi; }
  Real period() const { return 2 / c(); }

  // Wallstedt & Guilkey 2008, Eq. (61): zero normal stress at R_I and R_O, u(R_O) = A.
  Real c3() const { return -2 / (R_O * R_O * (R_O - 3 * R_I)); }
  Real c2() const { return 3 * (R_O + R_I) / (R_O * R_O * (R_O - 3 * R_I)); }
  Real c1() const { return -6 * R_I / (R_O * (R_O - 3 * R_I)); }
  /// Radial profile g(R) = c3 R^3 + c2 R^2 + c1 R and its derivatives (Wallstedt & Guilkey 2008, Eq. (60):
  /// u = A cos(c pi t) g(R)).
  Real g(Real R) const { return ((c3() * R + c2()) * R + c1()) * R; }
  Real dg(Real R) const { return (3 * c3() * R + 2 * c2()) * R + c1(); }
  Real d2g(Real R) const { return 6 * c3() * R + 2 * c2(); }

  /// Largest amplitude with positive radial and hoop stretches everywhere (1 + A g' > 0, 1 + A g/R > 0).
  Real max_amplitude() const {
    Real worst = 0;
    for (int k = 0; k <= 1000; ++k) {
      const Real R = R_I + (R_O - R_I) * k / 1000;
      worst = std::max({worst, -dg(R), -g(R) / R});
    }
    return worst > 0 ? 1 / worst : 1e300;
  }

  /// Wallstedt & Guilkey 2008, Eq. (62).
  Vec<2> displacement(const Vec<2>& X, Real t) const {
    const Real R = X.norm();
    return A * std::cos(omega() * t) * g(R) / R * X;
  }
  Vec<2> velocity(const Vec<2>& X, Real t) const {
    const Real R = X.norm();
    return -omega() * A * std::sin(omega() * t) * g(R) / R * X;
  }
  /// a = d^2u/dt^2 = -(c pi)^2 u.
  Vec<2> acceleration(const Vec<2>& X, Real t) const { return -omega() * omega() * displacement(X, t); }
  /// F = I + A cos(c pi t) [g' n n^T + (g/R)(I - n n^T)], n = X/R.
  Mat<2> deformation_gradient(const Vec<2>& X, Real t) const {
    const Real R = X.norm();
    const Vec<2> n = X / R;
    const Mat<2> nn = n * n.transpose();
    const Real T = A * std::cos(omega() * t);
    return Mat<2>::Identity() + T * (dg(R) * nn + g(R) / R * (Mat<2>::Identity() - nn));
  }
  /// b = a - (1/rho0) Div P. In polar reference coordinates F = diag(F_rr, F_tt) with F_rr = 1 + T g',
  /// F_tt = 1 + T g/R, so P = mu diag(F_rr - 1/F_rr, F_tt - 1/F_tt) and
  /// (Div P)_R = dP_RR/dR + (P_RR - P_TT)/R, dP_RR/dR = mu (1 + 1/F_rr^2) T g''; a = -(c pi)^2 u.
  Vec<2> body_force(const Vec<2>& X, Real t) const {
    const Real R = X.norm();
    const Real T = A * std::cos(omega() * t);
    const Real F_rr = 1 + T * dg(R), F_tt = 1 + T * g(R) / R;
    const Real P_rr = mat.mu * (F_rr - 1 / F_rr), P_tt = mat.mu * (F_tt - 1 / F_tt);
    const Real div_P = mat.mu * (1 + 1 / (F_rr * F_rr)) * T * d2g(R) + (P_rr - P_tt) / R;
    const Real a = -omega() * omega() * T * g(R);
    return (a - div_P / mat.rho0) / R * X;
  }

  /// The quarter ring on the grid [0, 1.25 R_O]^2 (room for the expansion and the kernels) with h =
  /// R_O/cells.
  void configure(SimulationSpec<2>& spec, int cells) const {
    spec.h = R_O / cells;
    const int n = static_cast<int>(std::ceil(1.25 * cells));
    spec.cells = {n, n};
    spec.boundary.faces[0].type = FaceType::symmetry;  // X = 0
    spec.boundary.faces[2].type = FaceType::symmetry;  // Y = 0
  }
  /// Lattice particles whose centres lie in the ring (the "stair-stepped" surfaces of Sec. 6.2.1).
  void seed(ParticleSet<2>& p, Real spacing) const {
    fill_box<2>(p, Vec<2>::Zero(), Vec<2>::Constant(R_O), spacing, mat.rho0, 0, {}, [this](const Vec<2>& X) {
      const Real R = X.norm();
      return R >= R_I && R <= R_O;
    });
  }
};

}  // namespace mpm

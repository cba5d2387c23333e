#pragma once
/// A standing shear wave along the diagonal of the periodic unit square (plane strain): an exact solution of
/// the Neo-Hookean equations of motion without body force, for any amplitude. The displacement
///   u = A e sin(k n.X) cos(omega t),  e = (1, 1)/sqrt 2,  n = (-1, 1)/sqrt 2,  k = 2 pi sqrt 2,
/// is a simple shear F = I + gamma e (x) n with gamma = A k cos(k n.X) cos(omega t), so J = 1 and the first
/// Piola-Kirchhoff stress of the Neo-Hookean law, P = mu (F - F^-T) + lambda ln J F^-T = mu gamma (e (x) n +
/// n (x) e), has Div P = mu (d gamma / d(n.X)) e; rho0 d^2u/dt^2 = Div P then holds with omega = k sqrt(mu /
/// rho0). Along the axes F_xx = 1 - gamma/2 and F_yy = 1 + gamma/2: past gamma = 2 (A > 1 / (pi sqrt 2) =
/// 0.225) cpGIMP's half-lengths l_0 F_dd leave (0, h/2] and the run stops, while CPDI's parallelograms follow
/// F.
#include <cmath>
#include <limits>
#include <numbers>

#include "mpm/core/types.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {

struct DiagonalShearWave {
  static constexpr int dim = 2;
  static constexpr bool periodic =
      true;        ///< unit period along each axis: positions wrap, errors are the nearest image
  Real A;          ///< displacement amplitude [m]
  NeoHookean mat;  ///< Lame constants and reference density

  static Vec<2> e() { return Vec<2>(1, 1) / std::numbers::sqrt2; }
  static Vec<2> n() { return Vec<2>(-1, 1) / std::numbers::sqrt2; }
  static Real k() { return 2 * std::numbers::pi * std::numbers::sqrt2; }
  /// The dilatational wave speed sqrt((lambda + 2 mu) / rho0), the CFL's reference (`--cfl-speed reference`).
  Real c() const { return std::sqrt((mat.lambda + 2 * mat.mu) / mat.rho0); }
  /// omega = k c_s, c_s = sqrt(mu / rho0) the shear wave speed.
  Real omega() const { return k() * std::sqrt(mat.mu / mat.rho0); }
  /// No amplitude inverts a simple shear (J = 1).
  Real max_amplitude() const { return std::numeric_limits<Real>::infinity(); }
  Real period() const { return 2 * std::numbers::pi / omega(); }

  Vec<2> displacement(const Vec<2>& X, Real t) const {
    return A * std::sin(k() * n().dot(X)) * std::cos(omega() * t) * e();
  }
  Vec<2> velocity(const Vec<2>& X, Real t) const {
    return -A * omega() * std::sin(k() * n().dot(X)) * std::sin(omega() * t) * e();
  }
  Vec<2> acceleration(const Vec<2>& X, Real t) const { return -omega() * omega() * displacement(X, t); }
  /// F = I + gamma e (x) n, gamma = A k cos(k n.X) cos(omega t).
  Mat<2> deformation_gradient(const Vec<2>& X, Real t) const {
    const Real gamma = A * k() * std::cos(k() * n().dot(X)) * std::cos(omega() * t);
    return Mat<2>::Identity() + gamma * e() * n().transpose();
  }
  Vec<2> body_force(const Vec<2>&, Real) const { return Vec<2>::Zero(); }

  /// The unit square, periodic along both axes.
  void configure(SimulationSpec<2>& spec, int cells) const {
    spec.h = 1.0 / cells;
    spec.cells.fill(cells);
    for (FaceCondition<2>& f : spec.boundary.faces) f.type = FaceType::periodic;
  }
  void seed(ParticleSet<2>& p, Real spacing) const {
    fill_box<2>(p, Vec<2>::Zero(), Vec<2>::Ones(), spacing, mat.rho0, 0);
  }
};

}  // namespace mpm

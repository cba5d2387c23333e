#pragma once
/// Manufactured solution with axis-aligned displacement in the unit square (plane strain) or cube.
/// Wallstedt & Guilkey 2008, Sec. 5.1, Eq. (56), Eq. (57), Eq. (58), Eq. (59); in 3-D a third component of
/// the same form with its own phase, u_z = A sin(pi Z) cos(c pi t + pi/3).
#include <cmath>
#include <numbers>

#include "mpm/core/types.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {

template <int Dim>
struct AxisAligned {
  static_assert(Dim == 2 || Dim == 3);
  static constexpr int dim = Dim;
  Real A;          ///< displacement amplitude [m]
  NeoHookean mat;  ///< Lame constants and reference density

  Real young() const { return mat.mu * (3 * mat.lambda + 2 * mat.mu) / (mat.lambda + mat.mu); }
  /// c^2 = E / rho0 (Wallstedt & Guilkey 2008, Eq. (56)).
  Real c() const { return std::sqrt(young() / mat.rho0); }
  Real omega() const { return c() * std::numbers::pi; }
  /// Largest amplitude with det F > 0 everywhere (F_dd = 1 + A pi cos(pi X_d) T_d(t)).
  Real max_amplitude() const { return 1 / std::numbers::pi; }
  /// One period of the motion [s].
  Real period() const { return 2 / c(); }

  /// Time factor of component d: cos(c pi t), sin(c pi t) (Wallstedt & Guilkey 2008, Eq. (56)), cos(c pi t +
  /// pi/3); and its derivative.
  Real T(int d, Real t) const { return std::cos(omega() * t - phase(d)); }
  Real dT(int d, Real t) const { return -omega() * std::sin(omega() * t - phase(d)); }
  static Real phase(int d) { return d == 0 ? 0 : (d == 1 ? std::numbers::pi / 2 : -std::numbers::pi / 3); }

  /// u_d = A sin(pi X_d) T_d(t), Wallstedt & Guilkey 2008, Eq. (56).
  Vec<Dim> displacement(const Vec<Dim>& X, Real t) const {
    Vec<Dim> u;
    for (int d = 0; d < Dim; ++d) u[d] = A * std::sin(std::numbers::pi * X[d]) * T(d, t);
    return u;
  }
  Vec<Dim> velocity(const Vec<Dim>& X, Real t) const {
    Vec<Dim> v;
    for (int d = 0; d < Dim; ++d) v[d] = A * std::sin(std::numbers::pi * X[d]) * dT(d, t);
    return v;
  }
  /// a = d^2u/dt^2 = -omega^2 u: every T_d is a cosine of omega t.
  Vec<Dim> acceleration(const Vec<Dim>& X, Real t) const { return -omega() * omega() * displacement(X, t); }
  /// F = diag(1 + A pi cos(pi X_d) T_d(t)), Wallstedt & Guilkey 2008, Eq. (57).
  Mat<Dim> deformation_gradient(const Vec<Dim>& X, Real t) const {
    Mat<Dim> F = Mat<Dim>::Zero();
    for (int d = 0; d < Dim; ++d)
      F(d, d) = 1 + A * std::numbers::pi * std::cos(std::numbers::pi * X[d]) * T(d, t);
    return F;
  }
  /// Body acceleration b = a - Div P / rho0, Wallstedt & Guilkey 2008, Eq. (59), with K = ln det F (in 2-D
  /// F_zz = 1).
  Vec<Dim> body_force(const Vec<Dim>& X, Real t) const {
    const Real pi = std::numbers::pi;
    const Vec<Dim> u = displacement(X, t);
    const Mat<Dim> F = deformation_gradient(X, t);
    const Real K = std::log(F.determinant());
    Vec<Dim> b;
    for (int d = 0; d < Dim; ++d) {
      const Real Fd2 = F(d, d) * F(d, d);
      b[d] = pi * pi * u[d] / mat.rho0 * (mat.lambda / Fd2 * (1 - K) + mat.mu * (1 + 1 / Fd2) - young());
    }
    return b;
  }

  /// The unit square or cube on a grid of the same extent; u_d is odd about X_d = 0 and 1, so every face is a
  /// symmetry plane.
  void configure(SimulationSpec<Dim>& spec, int cells) const {
    spec.h = 1.0 / cells;
    spec.cells.fill(cells);
    for (FaceCondition<Dim>& f : spec.boundary.faces) f.type = FaceType::symmetry;
  }
  void seed(ParticleSet<Dim>& p, Real spacing) const {
    fill_box<Dim>(p, Vec<Dim>::Zero(), Vec<Dim>::Ones(), spacing, mat.rho0, 0);
  }
};

}  // namespace mpm

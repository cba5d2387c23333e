#pragma once
/// Manufactured solution with axis-aligned displacement in the unit square (plane strain).
/// Wallstedt & Guilkey 2008, Sec. 5.1, Eqs (56)-(59).
#include <cmath>
#include <numbers>

#include "mpm/core/types.hpp"
#include "mpm/integrators/spec.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {

struct AxisAligned {
  static constexpr int dim = 2;
  Real A;          ///< displacement amplitude [m]
  NeoHookean mat;  ///< Lame constants and reference density

  Real young() const { return mat.mu * (3 * mat.lambda + 2 * mat.mu) / (mat.lambda + mat.mu); }
  /// c^2 = E / rho0 (Eq. 56).
  Real c() const { return std::sqrt(young() / mat.rho0); }
  /// Largest amplitude with det F > 0 everywhere (F_XX = 1 + A pi cos(pi X) cos(c pi t)).
  Real max_amplitude() const { return 1 / std::numbers::pi; }
  /// One period of the motion [s].
  Real period() const { return 2 / c(); }

  /// u = (A sin(pi X) cos(c pi t), A sin(pi Y) sin(c pi t)), Eq. (56).
  Vec<2> displacement(const Vec<2>& X, Real t) const {
    const Real pi = std::numbers::pi, w = c() * pi;
    return {A * std::sin(pi * X[0]) * std::cos(w * t), A * std::sin(pi * X[1]) * std::sin(w * t)};
  }
  Vec<2> velocity(const Vec<2>& X, Real t) const {
    const Real pi = std::numbers::pi, w = c() * pi;
    return {-w * A * std::sin(pi * X[0]) * std::sin(w * t), w * A * std::sin(pi * X[1]) * std::cos(w * t)};
  }
  /// F = diag(1 + A pi cos(pi X) cos(c pi t), 1 + A pi cos(pi Y) sin(c pi t)), Eq. (57).
  Mat<2> deformation_gradient(const Vec<2>& X, Real t) const {
    const Real pi = std::numbers::pi, w = c() * pi;
    Mat<2> F = Mat<2>::Zero();
    F(0, 0) = 1 + A * pi * std::cos(pi * X[0]) * std::cos(w * t);
    F(1, 1) = 1 + A * pi * std::cos(pi * X[1]) * std::sin(w * t);
    return F;
  }
  /// Body acceleration b = a - Div P / rho0, Eq. (59).
  Vec<2> body_force(const Vec<2>& X, Real t) const {
    const Real pi = std::numbers::pi;
    const Vec<2> u = displacement(X, t);
    const Mat<2> F = deformation_gradient(X, t);
    const Real K = std::log(F(0, 0) * F(1, 1));
    Vec<2> b;
    for (int d = 0; d < 2; ++d) {
      const Real Fd2 = F(d, d) * F(d, d);
      b[d] = pi * pi * u[d] / mat.rho0 * (mat.lambda / Fd2 * (1 - K) + mat.mu * (1 + 1 / Fd2) - young());
    }
    return b;
  }

  /// The unit square on a grid of the same extent; u_x is odd about X = 0, 1 and u_y about Y = 0, 1, so all
  /// four faces are symmetry planes.
  void configure(SimulationSpec<2>& spec, int cells) const {
    spec.h = 1.0 / cells;
    spec.cells = {cells, cells};
    for (FaceCondition<2>& f : spec.boundary.faces) f.type = FaceType::symmetry;
  }
  void seed(ParticleSet<2>& p, Real spacing) const {
    fill_box<2>(p, Vec<2>::Zero(), Vec<2>::Ones(), spacing, mat.rho0, 0);
  }
};

}  // namespace mpm

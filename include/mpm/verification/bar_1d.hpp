#pragma once
/// Manufactured solution for a 1-D fixed-fixed bar: u = A sin(2 pi X / L) cos(c pi t / L), Neo-Hookean with
/// zero Poisson ratio, sigma = P = (E/2)(F - 1/F) (Wallstedt & Guilkey 2008, Eq. (28); in 1-D P = J sigma / F
/// = sigma). The body force follows from b = a - (1/rho0) dP/dX (Wallstedt & Guilkey 2008, Eq. (52)).
#include <cmath>
#include <numbers>

#include "mpm/core/types.hpp"
#include "mpm/explicit/spec.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {

struct Bar1D {
  static constexpr int dim = 1;
  Real A;          ///< displacement amplitude [m]
  NeoHookean mat;  ///< lambda = 0, mu = E/2
  Real L = 1;      ///< bar length [m]

  Real young() const { return 2 * mat.mu; }
  Real c() const { return std::sqrt(young() / mat.rho0); }
  Real k() const { return 2 * std::numbers::pi / L; }
  Real omega() const { return c() * std::numbers::pi / L; }
  /// Largest amplitude with F > 0 everywhere (F = 1 + A k cos(k X) cos(omega t)).
  Real max_amplitude() const { return 1 / k(); }
  Real period() const { return 2 * std::numbers::pi / omega(); }

  Vec<1> displacement(const Vec<1>& X, Real t) const {
    return Vec<1>(A * std::sin(k() * X[0]) * std::cos(omega() * t));
  }
  Vec<1> velocity(const Vec<1>& X, Real t) const {
    return Vec<1>(-omega() * A * std::sin(k() * X[0]) * std::sin(omega() * t));
  }
  /// a = d^2u/dt^2 = -omega^2 u.
  Vec<1> acceleration(const Vec<1>& X, Real t) const { return -omega() * omega() * displacement(X, t); }
  Mat<1> deformation_gradient(const Vec<1>& X, Real t) const {
    return Mat<1>(1 + A * k() * std::cos(k() * X[0]) * std::cos(omega() * t));
  }
  /// b = a - (1/rho0) dP/dX with a = -omega^2 u and dP/dX = (E/2)(1 + 1/F^2) dF/dX, dF/dX = -k^2 u.
  Vec<1> body_force(const Vec<1>& X, Real t) const {
    const Real u = displacement(X, t)[0];
    const Real F = deformation_gradient(X, t)(0, 0);
    return Vec<1>(-omega() * omega() * u + young() / (2 * mat.rho0) * (1 + 1 / (F * F)) * k() * k() * u);
  }

  /// The bar [0, L] on a grid of the same extent; u is odd about both ends, so they are symmetry planes
  /// (zero normal velocity, mirrored ghost nodes), which is exact for every kernel.
  void configure(SimulationSpec<1>& spec, int cells) const {
    spec.h = L / cells;
    spec.cells = {cells};
    for (FaceCondition<1>& f : spec.boundary.faces) f.type = FaceType::symmetry;
  }
  void seed(ParticleSet<1>& p, Real spacing) const {
    fill_box<1>(p, Vec<1>::Zero(), Vec<1>(L), spacing, mat.rho0, 0);
  }
};

}  // namespace mpm

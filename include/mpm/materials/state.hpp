#pragma once
/// Per-particle state of the rate-form materials, stored as a structure of arrays by the particle set.
#include <cstddef>
#include <vector>

#include "mpm/core/types.hpp"

namespace mpm {

/// Empty while every material is hyperelastic (its stress follows from F alone).
struct MaterialState {
  std::vector<SymTensor<3>> sigma;  ///< Cauchy stress with the out-of-plane (zz or hoop) component [Pa]
  std::vector<Real> eps_bar;        ///< equivalent plastic strain (Sulsky & Kaul 2004, Eq. (2.1.18))
  std::vector<Real> temperature;    ///< temperature rise from plastic work (Sulsky & Kaul 2004, Eq. (2.3.5)) [K]
  std::vector<Real> energy;         ///< internal energy (Sulsky & Kaul 2004, Eq. (2.2.16)) [J, per unit thickness or radian]
  std::vector<Real> stretch3;       ///< out-of-plane stretch: 1 (plane strain), F_zz (plane stress), r/R (axisymmetric)

  bool empty() const { return sigma.empty(); }
  /// n unstressed particles.
  void resize(std::size_t n) {
    *this = MaterialState{};
    resize_keeping(n);
  }
  /// Grow (or shrink) to n particles, keeping the first ones' state; new particles start unstressed.
  void resize_keeping(std::size_t n) {
    sigma.resize(n, SymTensor<3>{});
    eps_bar.resize(n, 0);
    temperature.resize(n, 0);
    energy.resize(n, 0);
    stretch3.resize(n, 1);
  }
  static constexpr std::size_t bytes_per_particle() { return sizeof(SymTensor<3>) + 4 * sizeof(Real); }
};

}  // namespace mpm

#pragma once
/// Per-particle state of the rate-form materials, stored as a structure of arrays by the particle set.
#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "mpm/core/types.hpp"

namespace mpm {

/// The most internal variables a law keeps per particle beyond the stress and the plastic strain (a law
/// declares its own in `state_columns`; material.hpp checks that each fits).
inline constexpr std::size_t internal_columns = 1;
/// A particle's internal variables, in the order its law declares them (0 where its law declares fewer).
using InternalState = std::array<Real, internal_columns>;

/// Internal variables not given: NaN in every column. A particle file may give some (a law's state columns);
/// the others, and those of every seeded particle, start from the law's initial state (start_internal_state).
inline constexpr InternalState unset_internal_state = [] {
  InternalState s;
  s.fill(std::numeric_limits<Real>::quiet_NaN());
  return s;
}();

/// One internal variable a law declares: its name in frames and its unit.
struct StateColumn {
  const char* name;
  const char* unit;
};

/// Empty while every material is hyperelastic (its stress follows from F alone).
struct MaterialState {
  std::vector<SymTensor<3>> sigma;  ///< Cauchy stress with the out-of-plane (zz or hoop) component [Pa]
  std::vector<Real> eps_bar;        ///< equivalent plastic strain (Sulsky & Kaul 2004, Eq. (2.1.18))
  std::vector<Real>
      temperature;  ///< temperature rise from plastic work (Sulsky & Kaul 2004, Eq. (2.3.5)) [K]
  std::vector<Real>
      energy;  ///< internal energy (Sulsky & Kaul 2004, Eq. (2.2.16)) [J, per unit thickness or radian]
  std::vector<Real>
      stretch3;  ///< out-of-plane stretch: 1 (plane strain), F_zz (plane stress), r/R (axisymmetric)
  /// The internal variables each law declares; kept (keeps_internal) only where a law of the table declares
  /// some, so that the other runs neither store nor move them (start_internal_state).
  std::vector<InternalState> internal;
  bool keeps_internal = false;

  bool empty() const { return sigma.empty(); }
  /// n unstressed particles (keeping the internal variables or not, as before).
  void resize(std::size_t n) {
    const bool keep = keeps_internal;
    *this = MaterialState{};
    keeps_internal = keep;
    resize_keeping(n);
  }
  /// Grow (or shrink) to n particles, keeping the first ones' state; new particles start unstressed, their
  /// internal variables unset.
  void resize_keeping(std::size_t n) {
    sigma.resize(n, SymTensor<3>{});
    eps_bar.resize(n, 0);
    temperature.resize(n, 0);
    energy.resize(n, 0);
    stretch3.resize(n, 1);
    internal.resize(keeps_internal ? n : 0, unset_internal_state);
  }
  /// Particle i's internal variables: zero where no law of the table declares any.
  InternalState internal_at(std::size_t i) const { return keeps_internal ? internal[i] : InternalState{}; }
  void set_internal(std::size_t i, const InternalState& values) {
    if (keeps_internal) internal[i] = values;
  }
  /// The bytes per particle, with the internal variables where a law may keep them (an upper bound
  /// otherwise).
  static constexpr std::size_t bytes_per_particle() {
    return sizeof(SymTensor<3>) + 4 * sizeof(Real) + sizeof(InternalState);
  }
};

}  // namespace mpm

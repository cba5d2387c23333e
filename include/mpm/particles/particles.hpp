#pragma once
/// Material points stored as a structure of arrays.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "mpm/core/simd.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/state.hpp"

namespace mpm {

/// How a set's current half-lengths l_p follow from l_p^0: none kept (a kernel that reads none), l_p = l_p^0
/// (uGIMP, CPDI), or l_p = l_p^0 diag(F_p) (cpGIMP: Wallstedt & Guilkey 2008, Eq. (63)), bounded
/// (deformed_half_length).
enum class HalfLengths : std::uint8_t { none, fixed, deformed };

/// The least fraction of its reference half-length l^0 a cpGIMP domain keeps along an axis
/// (deformed_half_length). Measured on the spinning disk of CpdiSpin.*: with 1/8 or less a rim particle
/// inverts within five steps of its domain reaching the floor (its outer nodes' weight vanishes faster than
/// their gradient, the light nodes of linear MPM); with 1/4 and 1/2 the disk completes the turn.
inline constexpr Real least_domain_stretch = 0.25;

/// cpGIMP's half-length along one axis from l^0 and F's diagonal entry F_dd: l = l^0 F_dd (Wallstedt &
/// Guilkey 2008, Eq. (63)) where it lies in [l^0 least_domain_stretch, bound], `bound` the reach of the
/// kernel's stencil. Outside, the domain the stencil weighs is bounded rather than the run stopped: |l^0
/// F_dd| where a rotation past a right angle turns F_dd negative, kept within the same interval
/// (docs/kernels.md, "Bounded cpGIMP domains"). For Real or RealLanes.
template <class T>
[[gnu::always_inline]] inline T deformed_half_length(const T& l0, const T& F_dd, Real bound) {
  return simd::min(simd::max(simd::abs(l0 * F_dd), l0 * least_domain_stretch), T{} + bound);
}

/// The 2^Dim corners of a particle's domain (CPDI2), column c corner c, whose reference signs are the bits of
/// c (CpdiKernel::sign) [m].
template <int Dim>
using Corners = Eigen::Matrix<Real, Dim, 1 << Dim>;

/// One array per particle field. Positions and stresses are in the current configuration.
template <int Dim>
struct ParticleSet {
  std::vector<Vec<Dim>> x;              ///< current position x_p [m]
  std::vector<Vec<Dim>> X;              ///< reference position X_p [m]
  std::vector<Vec<Dim>> v;              ///< velocity v_p [m/s]
  std::vector<Mat<Dim>> F;              ///< deformation gradient F_p
  std::vector<Real> m;                  ///< mass m_p [kg]
  std::vector<Real> V0;                 ///< reference volume V_p^0 [m^Dim]
  std::vector<Real> V;                  ///< current volume V_p = V_p^0 det F_p [m^Dim]
  std::vector<SymTensor<Dim>> sigma;    ///< Cauchy stress [Pa]
  std::vector<std::uint16_t> material;  ///< index into the material table
  /// The grid velocity field the particle projects to: 0 unless contact gives its body a field of its own
  /// (ContactSpec; Bardenhagen, Brackbill & Sulsky 2000).
  std::vector<std::uint16_t> field;
  /// Stable identity: the particle's index in the set as seeded, kept through removals, restarts, the
  /// engine's reordering of the arrays and (in a distributed run) moves between ranks.
  std::vector<std::int64_t> id;
  /// State of the rate-form materials (sized by the engine when a rate-form material is present). Its sigma
  /// is then every particle's stress, the one P2G reads; sigma above is kept for the Neo-Hookean particles
  /// only.
  MaterialState state;
  /// APIC's affine matrix B_p [m^2/s] (Jiang et al. 2015; transfer/g2p.hpp's g2p_affine); empty unless the
  /// run transfers with APIC.
  std::vector<Mat<Dim>> B;
  /// CPDI2's domain corners (Sadeghirad, Brannon & Guilkey 2013; shape/cpdi2.hpp); empty unless the kernel is
  /// "cpdi2".
  std::vector<Corners<Dim>> corners;
  /// Reference half-lengths l_p^0 of the particles' domains [m], which GIMP and CPDI read
  /// (shape/stencil.hpp's reads_half_lengths); seeded with every particle, and emptied by an engine whose
  /// kernel does not read them (drop_half_lengths). The current ones follow from them (half_length).
  std::vector<Vec<Dim>> l0;
  /// How the current half-lengths follow from l0: the same on every rank of a run, also on one that holds no
  /// particle.
  HalfLengths half_lengths = HalfLengths::fixed;
  /// The largest half-length the kernel's stencil holds [m], to which deformed half-lengths are bounded
  /// (deformed_half_length); set by the engine with half_lengths.
  Real max_half_length = std::numeric_limits<Real>::infinity();

  std::size_t size() const { return x.size(); }

  /// Append an undeformed, stress-free particle; its id is its index in the set.
  void add(const Vec<Dim>& position, const Vec<Dim>& velocity, Real mass, Real volume,
           const Vec<Dim>& half_length, std::uint16_t material_id) {
    x.push_back(position);
    X.push_back(position);
    v.push_back(velocity);
    F.push_back(Mat<Dim>::Identity());
    m.push_back(mass);
    V0.push_back(volume);
    V.push_back(volume);
    l0.push_back(half_length);
    sigma.push_back(SymTensor<Dim>{});
    material.push_back(material_id);
    field.push_back(0);
    id.push_back(static_cast<std::int64_t>(id.size()));
  }

  /// Room for n particles in every array, so that seeding grows no array past what it needs.
  void reserve(std::size_t n) {
    for (auto* a : {&x, &X, &v, &l0}) a->reserve(n);
    F.reserve(n);
    for (auto* a : {&m, &V0, &V}) a->reserve(n);
    sigma.reserve(n);
    material.reserve(n);
    field.reserve(n);
    id.reserve(n);
  }

  /// Call fn(array) for every per-particle array, the material state's, APIC's, CPDI2's and the half-lengths
  /// included (some may be empty).
  template <class Fn>
  void for_each_array(Fn&& fn) {
    for_each_field(fn);
    for_each_state_array(fn);
    fn(B);
    fn(corners);
    fn(l0);
  }
  /// Call fn(array) for every array of the material state, the internal variables where it keeps them.
  template <class Fn>
  void for_each_state_array(Fn&& fn) {
    fn(state.sigma), fn(state.eps_bar), fn(state.temperature), fn(state.energy), fn(state.stretch3);
    if (state.keeps_internal) fn(state.internal);
  }
  /// Call fn(array) for every array every particle has: all but the material state's and the optional ones.
  template <class Fn>
  void for_each_field(Fn&& fn) {
    fn(x), fn(X), fn(v), fn(F), fn(m), fn(V0), fn(V), fn(sigma), fn(material), fn(field), fn(id);
  }

  /// The current half-length l_p of particle i (HalfLengths), or zero where the set keeps none.
  Vec<Dim> half_length(std::size_t i) const {
    switch (half_lengths) {
      case HalfLengths::none:
        return Vec<Dim>::Zero();
      case HalfLengths::fixed:
        return l0[i];
      case HalfLengths::deformed: {
        Vec<Dim> l;
        for (int d = 0; d < Dim; ++d) l[d] = deformed_half_length(l0[i][d], F[i](d, d), max_half_length);
        return l;
      }
    }
    return Vec<Dim>::Zero();
  }
  /// Particle i's half-lengths as F convects them, l^0 diag(F) (Wallstedt & Guilkey 2008, Eq. (63)),
  /// unbounded.
  Vec<Dim> convected_half_length(std::size_t i) const { return l0[i].cwiseProduct(F[i].diagonal()); }
  /// Particle i's half-lengths are bounded (deformed_half_length): l^0 F_dd leaves [l^0 least_domain_stretch,
  /// max_half_length] on an axis.
  bool half_length_bounded(std::size_t i) const {
    if (half_lengths != HalfLengths::deformed) return false;
    const Vec<Dim> l = convected_half_length(i);
    for (int d = 0; d < Dim; ++d)
      if (!(l[d] >= l0[i][d] * least_domain_stretch && l[d] <= max_half_length)) return true;
    return false;
  }
  /// Free l0, for a kernel that does not read it.
  void drop_half_lengths() {
    l0 = std::vector<Vec<Dim>>();  // a new empty vector: clear() would keep the storage
    half_lengths = HalfLengths::none;
  }

  /// Bytes of one particle's fields, with or without the half-lengths l0, without the rate-form state.
  static constexpr std::size_t bytes_per_particle(bool half_lengths) {
    return 3 * sizeof(Vec<Dim>) + sizeof(Mat<Dim>) + 3 * sizeof(Real) + sizeof(SymTensor<Dim>) +
           2 * sizeof(std::uint16_t) + sizeof(std::int64_t) + (half_lengths ? sizeof(Vec<Dim>) : 0);
  }
};

}  // namespace mpm

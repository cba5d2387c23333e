#pragma once
/// Material points stored as a structure of arrays.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mpm/core/types.hpp"
#include "mpm/materials/state.hpp"

namespace mpm {

/// How a set's current half-lengths l_p follow from l_p^0: none kept (a kernel that reads none), l_p = l_p^0
/// (uGIMP, CPDI), or l_p = l_p^0 diag(F_p) (cpGIMP: Wallstedt & Guilkey 2008, Eq. (63)).
enum class HalfLengths : std::uint8_t { none, fixed, deformed };

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
      case HalfLengths::deformed:
        return l0[i].cwiseProduct(F[i].diagonal());  // Wallstedt & Guilkey 2008, Eq. (63)
    }
    return Vec<Dim>::Zero();
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

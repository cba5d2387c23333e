#pragma once
/// What a deforming G2P pass does with each block's new deformation, as a policy of g2p: the Neo-Hookean stress
/// in lanes (the fast path when every material is Neo-Hookean), or the rates recorded for the stress-update stage
/// that visits each particle's material (rate-form and mixed tables).
#include <algorithm>
#include <vector>

#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/lanes.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// Sigma(F) of Wallstedt & Guilkey 2008, Eq. (55), in lanes; lambda and mu broadcast from the one material or
/// gathered by 16-bit material index.
struct NeoHookeanLanes {
  const std::vector<NeoHookean>& materials;
  static constexpr bool reads_velocity = false;  ///< needs no interpolated velocity

  /// A lane with an invalid J keeps its stress (the run stops).
  template <int Dim>
  [[gnu::always_inline]] void operator()(const LaneBlock& block, ParticleSet<Dim>& p, const RealLanes (&F)[Dim][Dim],
                                         const RealLanes& J, const simd::MaskLanes& valid,
                                         const RealLanes (&)[Dim][Dim], const RealLanes&, const RealLanes&) const {
    RealLanes lambda = simd::broadcast(materials[0].lambda), mu = simd::broadcast(materials[0].mu);
    if (materials.size() > 1) {
      const IntLanes material = block.load_indices(p.material) * reals_in<NeoHookean>;
      lambda = simd::gather(&materials[0].lambda, material);
      mu = simd::gather(&materials[0].mu, material);
    }
    RealLanes sigma_new[sym_size<Dim>];
    NeoHookean::cauchy<Dim>(F, J, lambda, mu, sigma_new);
    RecordLanes<SymTensor<Dim>> sigma;
    std::copy_n(sigma_new, sym_size<Dim>, sigma.begin());
    if (!simd::all(valid)) {
      const RecordLanes<SymTensor<Dim>> sigma_old = block.load(p.sigma);
      for (int c = 0; c < sym_size<Dim>; ++c) sigma[c] = valid ? sigma[c] : sigma_old[c];
    }
    block.store(p.sigma, sigma);
  }
};

/// Record each particle's velocity gradient [1/s] and, in axisymmetry, its hoop strain rate v_r / r [1/s] (r at
/// the start of the step) for the stress-update stage.
template <int Dim>
struct RecordRates {
  std::vector<Mat<Dim>>& grad_v;
  std::vector<Real>& hoop_rate;
  bool axisymmetric;
  static constexpr bool reads_velocity = true;  ///< needs the interpolated radial velocity v_r

  [[gnu::always_inline]] void operator()(const LaneBlock& block, ParticleSet<Dim>&, const RealLanes (&)[Dim][Dim],
                                         const RealLanes&, const simd::MaskLanes&, const RealLanes (&L)[Dim][Dim],
                                         const RealLanes& v_r, const RealLanes& r_start) const {
    RecordLanes<Mat<Dim>> record;  // column-major: entry (a, c) is Real a + c Dim
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) record[a + c * Dim] = L[a][c];
    block.store(grad_v, record);
    if (axisymmetric) block.store(hoop_rate, {v_r / r_start});
  }
};

}  // namespace mpm

#pragma once
/// What a deforming G2P pass does with each block's new deformation, as a policy of g2p: the Neo-Hookean
/// stress in lanes (when every material is Neo-Hookean), the Drucker-Prager step in lanes (when every
/// material is Drucker-Prager), or the rates recorded for the stress-update stage that visits each particle's
/// material (other rate-form and mixed tables). A deforming pass reaches them through LaneStress, one call a
/// block: the policies are compiled once per dimension (src/transfer/g2p_stress.cpp), not once per kernel and
/// pass.
#include <algorithm>
#include <vector>

#include "mpm/core/simd.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/lanes.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// The policy of a pass that does not deform (a Gather without deformation): g2p never calls it, so a pass
/// that only moves or accelerates the particles is compiled without one.
struct NoStress {
  static constexpr bool reads_velocity = false;
};

/// A deforming pass's block as g2p hands it to the stress: the new F and J = det F, the lanes whose J is
/// valid, the velocity gradient L (L[a][c] = d v_a / d x_c) and, where the policy reads them, the
/// interpolated radial velocity v_r and the radius at the start of the step. The policy clears the lanes of
/// `ok` it fails.
template <int Dim>
struct DeformedBlock {
  RealLanes F[Dim][Dim], J, L[Dim][Dim], v_r, r_start;
  simd::MaskLanes valid, ok;
};

/// Sigma(F) of Wallstedt & Guilkey 2008, Eq. (55), in lanes; lambda and mu broadcast from the one material or
/// gathered by 16-bit material index. A lane with an invalid J keeps its stress (the run stops).
template <int Dim>
struct NeoHookeanLanes {
  const std::vector<NeoHookean>& materials;
  static constexpr bool reads_velocity = false;  ///< needs no interpolated velocity
  /// The lanes that stay valid: those of `valid`.
  [[gnu::always_inline]] simd::MaskLanes operator()(const LaneBlock& block, ParticleSet<Dim>& p,
                                                    const RealLanes (&F)[Dim][Dim], const RealLanes& J,
                                                    const simd::MaskLanes& valid,
                                                    const RealLanes (&)[Dim][Dim], const RealLanes&,
                                                    const RealLanes&) const {
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
    return valid;
  }
};

/// Record each particle's velocity gradient [1/s] and, in axisymmetry, its hoop strain rate v_r / r [1/s] (r
/// at the start of the step) for the stress-update stage.
template <int Dim, bool Axisymmetric>
struct RecordRates {
  std::vector<Mat<Dim>>& grad_v;
  std::vector<Real>& hoop_rate;
  static constexpr bool reads_velocity = Axisymmetric;  ///< the hoop rate needs the interpolated v_r
  void apply(const LaneBlock& block, ParticleSet<Dim>& p, DeformedBlock<Dim>& d) const;
};

/// The rows of a table whose every material is Drucker-Prager; empty otherwise.
std::vector<DruckerPragerRow> drucker_prager_rows(const std::vector<Material>& materials);

/// The rate-form step of Drucker-Prager solids in lanes (rate_form_step's, the same bits): the strain and
/// spin increments of dL = dt grad v (and dt v_r / r in axisymmetry), the hypoelastic trial stress, the
/// return to a fixed strength (return_to_cone), the plastic strain, the internal energy with the mid-step
/// stress and the volume. The lanes of a material whose strength changes with the plastic strain take
/// rate_form_step itself (the regula falsi of return_with_softening). Plane strain (1-D, 2-D and 3-D) or
/// axisymmetric. A lane with an invalid J keeps its state (the run stops); a lane whose step fails is
/// reported.
template <int Dim, bool Axisymmetric>
struct DruckerPragerLanes {
  const std::vector<Material>& materials;
  const std::vector<DruckerPragerRow>& rows;
  Real dt;
  static constexpr bool reads_velocity = Axisymmetric;  ///< the hoop rate needs the interpolated v_r
  void apply(const LaneBlock& block, ParticleSet<Dim>& p, DeformedBlock<Dim>& d) const;
  bool any_softens() const;
};

/// The rate-form policies (RecordRates, DruckerPragerLanes) behind one type: g2p compiles a deforming pass
/// once for those that read (or do not read) the interpolated velocity, and calls the policy's apply once a
/// block. The Neo-Hookean stress is a policy of its own, inline in its pass: through a call it cost 3-7% of a
/// Neo-Hookean step (docs/build.md). `policy` must outlive the pass.
template <int Dim, bool ReadsVelocity>
class LaneStress {
 public:
  static constexpr bool reads_velocity = ReadsVelocity;
  template <class Policy>
  requires(Policy::reads_velocity == ReadsVelocity) explicit LaneStress(const Policy& policy)
      : policy_(&policy),
        apply_([](const void* q, const LaneBlock& block, ParticleSet<Dim>& p, DeformedBlock<Dim>& d) {
          static_cast<const Policy*>(q)->apply(block, p, d);
        }) {}
  /// The lanes that stay valid.
  [[gnu::always_inline]] simd::MaskLanes operator()(const LaneBlock& block, ParticleSet<Dim>& p,
                                                    const RealLanes (&F)[Dim][Dim], const RealLanes& J,
                                                    const simd::MaskLanes& valid,
                                                    const RealLanes (&L)[Dim][Dim], const RealLanes& v_r,
                                                    const RealLanes& r_start) const {
    DeformedBlock<Dim> d;
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) d.F[a][c] = F[a][c], d.L[a][c] = L[a][c];
    d.J = J, d.valid = valid, d.ok = valid, d.v_r = v_r, d.r_start = r_start;
    apply_(policy_, block, p, d);
    return d.ok;
  }

 private:
  const void* policy_;
  void (*apply_)(const void*, const LaneBlock&, ParticleSet<Dim>&, DeformedBlock<Dim>&);
};
}  // namespace mpm

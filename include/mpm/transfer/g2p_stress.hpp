#pragma once
/// What a deforming G2P pass does with each block's new deformation, as a policy of g2p: the Neo-Hookean
/// stress in lanes (when every material is Neo-Hookean), the Drucker-Prager step in lanes (when every
/// material is Drucker-Prager), or the rates recorded for the stress-update stage that visits each particle's
/// material (other rate-form and mixed tables).
#include <algorithm>
#include <iterator>
#include <vector>

#include "mpm/core/model_geometry.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/materials/material_step.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/materials/sym3.hpp"
#include "mpm/particles/lanes.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// The policy of a pass that does not deform (a Gather without deformation): g2p never calls it, so a pass
/// that only moves or accelerates the particles is compiled once, not once per stress policy.
struct NoStress {
  static constexpr bool reads_velocity = false;
};

/// Sigma(F) of Wallstedt & Guilkey 2008, Eq. (55), in lanes; lambda and mu broadcast from the one material or
/// gathered by 16-bit material index.
struct NeoHookeanLanes {
  const std::vector<NeoHookean>& materials;
  static constexpr bool reads_velocity = false;  ///< needs no interpolated velocity

  /// A lane with an invalid J keeps its stress (the run stops).
  template <int Dim>
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
template <int Dim>
struct RecordRates {
  std::vector<Mat<Dim>>& grad_v;
  std::vector<Real>& hoop_rate;
  bool axisymmetric;
  static constexpr bool reads_velocity = true;  ///< needs the interpolated radial velocity v_r

  [[gnu::always_inline]] simd::MaskLanes operator()(const LaneBlock& block, ParticleSet<Dim>&,
                                                    const RealLanes (&)[Dim][Dim], const RealLanes&,
                                                    const simd::MaskLanes& valid,
                                                    const RealLanes (&L)[Dim][Dim], const RealLanes& v_r,
                                                    const RealLanes& r_start) const {
    RecordLanes<Mat<Dim>> record;  // column-major: entry (a, c) is Real a + c Dim
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) record[a + c * Dim] = L[a][c];
    block.store(grad_v, record);
    if (axisymmetric) block.store(hoop_rate, {v_r / r_start});
    return valid;
  }
};

/// The rows of a table whose every material is Drucker-Prager; empty otherwise.
inline std::vector<DruckerPragerRow> drucker_prager_rows(const std::vector<Material>& materials) {
  std::vector<DruckerPragerRow> rows;
  for (const Material& material : materials) {
    const auto* m = std::get_if<DruckerPrager>(&material);
    if (!m) return {};
    rows.push_back({cone_strength(*m, 0), m->lambda(), m->strength.constant() ? 0.0 : 1.0});
  }
  return rows;
}

/// The rate-form step of Drucker-Prager solids in lanes (rate_form_step's, the same bits): the strain and
/// spin increments of dL = dt grad v (and dt v_r / r in axisymmetry), the hypoelastic trial stress, the
/// return to a fixed strength (return_to_cone), the plastic strain, the internal energy with the mid-step
/// stress and the volume. The lanes of a material whose strength changes with the plastic strain take
/// rate_form_step itself (the regula falsi of return_with_softening). Plane strain (1-D, 2-D and 3-D) or
/// axisymmetric.
template <int Dim, bool Axisymmetric>
struct DruckerPragerLanes {
  const std::vector<Material>& materials;
  const std::vector<DruckerPragerRow>& rows;
  Real dt;
  static constexpr bool reads_velocity = Axisymmetric;  ///< the hoop rate needs the interpolated v_r

  /// A lane with an invalid J keeps its state (the run stops); a lane whose step fails is reported.
  [[gnu::always_inline]] simd::MaskLanes operator()(const LaneBlock& block, ParticleSet<Dim>& p,
                                                    const RealLanes (&)[Dim][Dim], const RealLanes& J,
                                                    const simd::MaskLanes& valid,
                                                    const RealLanes (&L)[Dim][Dim], const RealLanes& v_r,
                                                    const RealLanes& r_start) const {
    MaterialState& s = p.state;
    ConeStrength<RealLanes> cone;
    RealLanes lambda, softens;
    {
      RealLanes* member[] = {&cone.G,       &cone.K, &cone.eta, &cone.xi_c,
                             &cone.eta_bar, &cone.t, &lambda,   &softens};
      static_assert(std::size(member) == reals_in<DruckerPragerRow>);
      const Real* row = &rows[0].cone.G;
      if (rows.size() == 1) {
        for (int k = 0; k < reals_in<DruckerPragerRow>; ++k) *member[k] = simd::broadcast(row[k]);
      } else {
        const IntLanes material = block.load_indices(p.material) * reals_in<DruckerPragerRow>;
        for (int k = 0; k < reals_in<DruckerPragerRow>; ++k) *member[k] = simd::gather(row + k, material);
      }
    }
    RealLanes dL[3][3] = {};
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) dL[a][c] = dt * L[a][c];
    StrainIncrement<RealLanes> step = strain_increment(dL);
    if constexpr (Axisymmetric) step.de(2, 2) = dt * (v_r / r_start);
    Sym3<RealLanes> sigma_n;
    const RecordLanes<SymTensor<3>> sigma_record = block.load(s.sigma);
    std::copy_n(sigma_record.begin(), 6, sigma_n.c.begin());
    const Sym3<RealLanes> trial = hypoelastic_trial(sigma_n, step, cone.G, lambda);
    const ConeTrial<RealLanes> yield = cone_trial(cone, trial);
    // Elastic blocks (most, in a body at rest) neither return nor read the plastic strain.
    const bool plastic = simd::any(yield.plastic) || any_softens();
    Sym3<RealLanes> sigma = trial;
    RealLanes eps_n{}, eps{};
    if (plastic) {
      const Sym3<RealLanes> returned = return_to_cone(cone, yield);
      for (int c = 0; c < 6; ++c) sigma.c[c] = yield.plastic ? returned.c[c] : trial.c[c];
      eps_n = block.load(s.eps_bar)[0];
      eps = yield.plastic ? eps_n + plastic_strain_increment(trial, sigma, cone.G) : eps_n;
    }
    // G2P set V = V0 det F: the step starts from V / det(I + dL) (times the hoop stretch).
    RealLanes I_dL[Dim][Dim];
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) I_dL[a][c] = (a == c ? 1 : 0) + dL[a][c];
    const RealLanes det_step = simd::determinant(I_dL), V = block.load(p.V0)[0] * J;
    RealLanes stretch3_n = simd::broadcast(1), stretch3 = stretch3_n, V_start = V / det_step;
    if constexpr (Axisymmetric) {
      stretch3_n = block.load(s.stretch3)[0];
      V_start = V_start * stretch3_n;
      stretch3 = stretch3_n * (1 + step.de(2, 2));
    }
    RealLanes energy = V_start * mid_step_work(sigma_n, sigma, step.de);  // Sulsky & Kaul 2004, Eq. (2.2.16)
    simd::MaskLanes ok = (det_step * stretch3 / stretch3_n > 0) & (stretch3 > 0);
    for (int k = 0; k < 6; ++k) ok &= sigma.c[k] - sigma.c[k] == 0;
    if (any_softens())
      for (int k = 0; k < block.active; ++k) {
        if (softens[k] == 0) continue;
        Mat<Dim> dL_k;
        for (int a = 0; a < Dim; ++a)
          for (int c = 0; c < Dim; ++c) dL_k(a, c) = dL[a][c][k];
        SymTensor<3> sigma_k;
        for (int c = 0; c < 6; ++c) sigma_k.c[c] = sigma_n.c[c][k];
        const MaterialStep one =
            rate_form_step<Dim>(std::get<DruckerPrager>(materials[p.material[block.index[k]]]), sigma_k,
                                eps_n[k], stretch3_n[k], V_start[k], dL_k, step.de(2, 2)[k],
                                Axisymmetric ? Geometry::axisymmetric : Geometry::plane_strain);
        for (int c = 0; c < 6; ++c) sigma.c[c][k] = one.sigma.c[c];
        eps[k] = one.eps_bar, energy[k] = one.energy, stretch3[k] = one.stretch3, ok[k] = one.ok ? -1 : 0;
      }
    // Store; a lane with an invalid J keeps its state.
    RecordLanes<SymTensor<3>> sigma_out;
    for (int c = 0; c < 6; ++c) sigma_out[c] = valid ? sigma.c[c] : sigma_n.c[c];
    block.store(s.sigma, sigma_out);  // what P2G reads (p.sigma is not kept with a material state)
    if (plastic) block.store(s.eps_bar, {valid ? eps : eps_n});
    block.store(s.energy, {block.load(s.energy)[0] + (valid ? energy : RealLanes{})});
    if constexpr (Axisymmetric) {
      stretch3 = valid ? stretch3 : stretch3_n;
      block.store(s.stretch3, {stretch3});
      block.store(p.V, {V * stretch3});
    }
    return valid & ok;
  }

  bool any_softens() const {
    for (const DruckerPragerRow& row : rows)
      if (row.softens != 0) return true;
    return false;
  }
};

}  // namespace mpm

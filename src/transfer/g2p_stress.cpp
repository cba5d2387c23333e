// The lane stress policies of a deforming G2P pass (mpm/transfer/g2p_stress.hpp), compiled once per
// dimension.
#include "mpm/transfer/g2p_stress.hpp"

#include <algorithm>
#include <iterator>

#include "mpm/materials/material_step.hpp"
#include "mpm/materials/sym3.hpp"

namespace mpm {

template <int Dim, bool Axisymmetric>
void RecordRates<Dim, Axisymmetric>::apply(const LaneBlock& block, ParticleSet<Dim>&,
                                           DeformedBlock<Dim>& d) const {
  RecordLanes<Mat<Dim>> record;  // column-major: entry (a, c) is Real a + c Dim
  for (int a = 0; a < Dim; ++a)
    for (int c = 0; c < Dim; ++c) record[a + c * Dim] = d.L[a][c];
  block.store(grad_v, record);
  if constexpr (Axisymmetric) block.store(hoop_rate, {d.v_r / d.r_start});
}

std::vector<DruckerPragerRow> drucker_prager_rows(const std::vector<Material>& materials) {
  std::vector<DruckerPragerRow> rows;
  for (const Material& material : materials) {
    const auto* m = std::get_if<DruckerPrager>(&material);
    if (!m) return {};
    rows.push_back({cone_strength(*m, 0), m->lambda(), m->strength.constant() ? 0.0 : 1.0});
  }
  return rows;
}

template <int Dim, bool Axisymmetric>
bool DruckerPragerLanes<Dim, Axisymmetric>::any_softens() const {
  for (const DruckerPragerRow& row : rows)
    if (row.softens != 0) return true;
  return false;
}

template <int Dim, bool Axisymmetric>
void DruckerPragerLanes<Dim, Axisymmetric>::apply(const LaneBlock& block, ParticleSet<Dim>& p,
                                                  DeformedBlock<Dim>& d) const {
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
    for (int c = 0; c < Dim; ++c) dL[a][c] = dt * d.L[a][c];
  StrainIncrement<RealLanes> step = strain_increment(dL);
  if constexpr (Axisymmetric) step.de(2, 2) = dt * (d.v_r / d.r_start);
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
  const RealLanes det_step = simd::determinant(I_dL), V = block.load(p.V0)[0] * d.J;
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
      const MaterialStep one = rate_form_step<Dim>(
          std::get<DruckerPrager>(materials[p.material[block.index[k]]]), sigma_k, eps_n[k], stretch3_n[k],
          V_start[k], dL_k, step.de(2, 2)[k], Axisymmetric ? Geometry::axisymmetric : Geometry::plane_strain);
      for (int c = 0; c < 6; ++c) sigma.c[c][k] = one.sigma.c[c];
      eps[k] = one.eps_bar, energy[k] = one.energy, stretch3[k] = one.stretch3, ok[k] = one.ok ? -1 : 0;
    }
  // Store; a lane with an invalid d.J keeps its state.
  RecordLanes<SymTensor<3>> sigma_out;
  for (int c = 0; c < 6; ++c) sigma_out[c] = d.valid ? sigma.c[c] : sigma_n.c[c];
  block.store(s.sigma, sigma_out);  // what P2G reads (p.sigma is not kept with a material state)
  if (plastic) block.store(s.eps_bar, {d.valid ? eps : eps_n});
  block.store(s.energy, {block.load(s.energy)[0] + (d.valid ? energy : RealLanes{})});
  if constexpr (Axisymmetric) {
    stretch3 = d.valid ? stretch3 : stretch3_n;
    block.store(s.stretch3, {stretch3});
    block.store(p.V, {V * stretch3});
  }
  d.ok &= ok;
}

template struct RecordRates<1, false>;
template struct RecordRates<2, false>;
template struct RecordRates<2, true>;  // axisymmetry is 2-D
template struct RecordRates<3, false>;
template struct DruckerPragerLanes<1, false>;
template struct DruckerPragerLanes<2, false>;
template struct DruckerPragerLanes<2, true>;
template struct DruckerPragerLanes<3, false>;

}  // namespace mpm

#pragma once
// The material stages of Simulation<Dim, Kernel>: the stress update after a deforming G2P pass (every
// material but the Neo-Hookean one, whose stress G2P computes in lanes when it is the only one), the 3 x 3
// stress of a particle. Included by simulation_impl.hpp.
#include <atomic>
#include <variant>

#include "mpm/explicit/simulation.hpp"
#include "mpm/materials/material_step.hpp"

namespace mpm {

template <int Dim, class Kernel>
SymTensor<3> Simulation<Dim, Kernel>::full_stress(std::size_t i) const {
  const ParticleSet<Dim>& p = particles_;
  const Material& material = spec_.materials[p.material[i]];
  if (is_rate_form(material)) return p.state.sigma[i];
  return neo_hookean_stress<Dim>(std::get<NeoHookean>(material), p.sigma[i], p.F[i].determinant());
}

// The stress of each particle from its material: Neo-Hookean from F (Wallstedt & Guilkey 2008, Eq. (55)), the
// others from the velocity gradient over the step (material_step). The hoop stretch accumulates
// 1 + dt v_r / r; the temperature rises with the plastic work (Sulsky & Kaul 2004, Eq. (2.3.5)).
template <int Dim, class Kernel>
ParticleFault Simulation<Dim, Kernel>::update_stress(Real dt) {
  ParticleSet<Dim>& p = particles_;
  MaterialState& s = p.state;
  std::atomic<std::int64_t> first_fault{ParticleFault::none};
  parallel_for(static_cast<std::ptrdiff_t>(p.size()), [&](std::ptrdiff_t i) {
    const Material& material = spec_.materials[p.material[i]];
    bool ok = true;
    if (is_rate_form(material)) {
      // G2P has advanced F and set V = V0 det F: the step starts from (I + dL)^-1 F and V / det(I + dL).
      const Mat<Dim> dL = dt * grad_v_[i];
      const Mat<Dim> step = Mat<Dim>::Identity() + dL;
      const Real V_start = p.V[i] / step.determinant() * s.stretch3[i];
      // Only the fluid reads F (its J): the solids' rate form needs none.
      const Mat<Dim> F_start =
          std::holds_alternative<NewtonianFluid>(material) ? Mat<Dim>(step.inverse() * p.F[i]) : p.F[i];
      const MaterialStep r = material_step<Dim>(material, s.sigma[i], s.eps_bar[i], s.stretch3[i],
                                                s.internal_at(i), V_start, p.V0[i], F_start, dL, dt,
                                                axisymmetric_ ? dt * hoop_rate_[i] : 0, spec_.geometry);
      ok = r.ok;
      s.sigma[i] = r.sigma;
      s.eps_bar[i] = r.eps_bar;
      s.set_internal(i, r.internal);
      s.energy[i] += r.energy;
      const auto* law = std::get_if<ElastoPlastic>(&material);
      if (law && law->specific_heat > 0) s.temperature[i] += r.work / (p.m[i] * law->specific_heat);
      s.stretch3[i] = r.stretch3;
      p.V[i] = p.V0[i] * p.F[i].determinant() * r.stretch3;
    } else {
      const Real J = p.F[i].determinant();
      ok = J > 0;
      if (ok) p.sigma[i] = std::get<NeoHookean>(material).template stress<Dim>(p.F[i], J);
      s.sigma[i] = full_stress(static_cast<std::size_t>(i));
    }
    if (ok) return;
    std::int64_t cur = first_fault.load(std::memory_order_relaxed);
    while (i < cur && !first_fault.compare_exchange_weak(cur, i)) {
    }
  });
  return ParticleFault{first_fault.load()};
}

}  // namespace mpm

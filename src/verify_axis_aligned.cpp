#include <cmath>
#include <numbers>

#include "mpm/core/errors.hpp"
#include "mpm/integrators/simulation.hpp"
#include "mpm/particles/generate.hpp"
#include "mpm/verification/axis_aligned.hpp"
#include "mpm/verification/study.hpp"

namespace mpm {

void validate(const VerifyOptions& o) {
  if (o.cells < 2) throw InputError("--cells: expected at least 2 cells per axis");
  if (o.ppc < 1) throw InputError("--ppc: expected at least 1 particle per cell per axis");
  if (!(o.cfl > 0 && o.cfl <= 1)) throw InputError("--cfl: expected a number in (0, 1]");
  if (!(o.amplitude >= 0 && o.amplitude < 1 / std::numbers::pi))
    throw InputError("--amplitude: expected 0 <= A < 1/pi (larger A inverts the material)");
  if (!(o.end_time >= 0)) throw InputError("--end-time: expected a non-negative time (0: one period)");
}

VerifyResult verify_axis_aligned(const VerifyOptions& o, const std::function<void(const ParticleSet<2>&)>& on_finish) {
  validate(o);
  const AxisAligned exact{o.amplitude, NeoHookean::from_young_poisson(1e7, 0.3, 1000)};
  SimulationSpec<2> spec;
  spec.h = 1.0 / o.cells;
  spec.cells = {o.cells, o.cells};
  spec.kernel = o.kernel;
  spec.integrator = o.integrator;
  spec.materials = {exact.mat};
  spec.cfl = o.cfl;
  for (FaceCondition<2>& f : spec.boundary.faces) f.type = FaceType::symmetry;
  spec.body_force = [exact](const Vec<2>& X, Real t) { return exact.body_force(X, t); };

  // Reference lattice, then the exact state at t = 0: x = X + u, v, F (stress and volume follow from F).
  ParticleSet<2> p;
  fill_box<2>(p, Vec<2>::Zero(), Vec<2>::Ones(), spec.h / o.ppc, exact.mat.rho0, 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] = p.X[i] + exact.displacement(p.X[i], 0);
    p.v[i] = exact.velocity(p.X[i], 0);
    p.F[i] = exact.deformation_gradient(p.X[i], 0);
    if (o.kernel == KernelKind::cpgimp)
      for (int d = 0; d < 2; ++d) p.l[i][d] = p.l0[i][d] * p.F[i](d, d);  // Eq. (63)
  }

  VerifyResult r;
  r.end_time = o.end_time > 0 ? o.end_time : exact.period();
  with_kernel(o.kernel, [&]<class K>() {
    Simulation<2, K> sim(spec, std::move(p));
    try {
      while (sim.time() < r.end_time * (1 - 1e-14)) {
        sim.step(r.end_time - sim.time());
        r.error.record(sim.particles(), sim.time(), exact);
      }
    } catch (const SimulationFailure& e) {
      r.ok = false;
      r.failure = e.what();
      r.error.linf = 1;
    }
    r.steps = sim.steps();
    if (on_finish) on_finish(sim.particles());
  });
  return r;
}

}  // namespace mpm

#include <array>
#include <cmath>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/verification/axis_aligned.hpp"
#include "mpm/verification/bar_1d.hpp"
#include "mpm/verification/expanding_ring.hpp"
#include "mpm/verification/nodal_error.hpp"
#include "mpm/verification/shear_wave.hpp"
#include "mpm/verification/study.hpp"

namespace mpm {

namespace {
constexpr std::array<std::string_view, 4> case_names{"axis-aligned", "bar-1d", "expanding-ring",
                                                     "shear-wave"};

template <int Dim, class Exact>
ParticleTable table_of(const ParticleSet<Dim>& p, const Exact& exact, Real t) {
  static constexpr const char* axis[] = {"x", "y", "z"};
  ParticleTable tab;
  for (int d = 0; d < Dim; ++d) tab.columns.push_back(std::string("X") + axis[d]);
  for (int d = 0; d < Dim; ++d) tab.columns.push_back(axis[d]);
  for (int d = 0; d < Dim; ++d) tab.columns.push_back(std::string("v") + axis[d]);
  tab.columns.push_back("J");
  for (int a = 0; a < Dim; ++a)
    for (int b = a; b < Dim; ++b) tab.columns.push_back(std::string("sigma_") + axis[a] + axis[b]);
  tab.columns.push_back("error");
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::vector<Real> row;
    for (int d = 0; d < Dim; ++d) row.push_back(p.X[i][d]);
    for (int d = 0; d < Dim; ++d) row.push_back(p.x[i][d]);
    for (int d = 0; d < Dim; ++d) row.push_back(p.v[i][d]);
    row.push_back(p.F[i].determinant());
    for (int a = 0; a < Dim; ++a)
      for (int b = a; b < Dim; ++b) row.push_back(p.sigma[i](a, b));
    row.push_back(displacement_error<Dim>(exact, p.x[i], p.X[i], t));
    tab.rows.push_back(std::move(row));
  }
  return tab;
}

/// The implicit engine's spec of the same problem: steps of the explicit CFL step, a tight Newton solve.
template <int Dim>
ImplicitSpec<Dim> implicit_spec_of(const SimulationSpec<Dim>& s, Real theta) {
  ImplicitSpec<Dim> is;
  is.grid_lo = s.grid_lo;
  is.h = s.h;
  is.cells = s.cells;
  is.kernel = s.kernel;
  is.transfer = s.transfer;
  is.materials = s.materials;
  is.boundary = s.boundary;
  is.gravity = s.gravity;
  is.body_force = s.body_force;
  is.theta = theta;
  is.step.cfl = s.cfl;
  is.step.dt = s.dt;
  is.newton.newton_tolerance = 1e-10;
  is.newton.linear_tolerance = 1e-6;
  return is;
}

/// Step a simulation to the end time, recording the error after every step: at the particles, or at the nodes
/// for the acceleration of the step (not on a first step whose acceleration is halved by design).
template <class Sim, class Exact>
void run_to_end(Sim& sim, const Exact& exact, const VerifyOptions& o, ParticleTable* final_state,
                VerifyResult& r) {
  const bool halved_start = !o.implicit &&
                            (o.integrator == Integrator::cd || o.integrator == Integrator::musl) &&
                            o.start == HalfStepStart::halve;
  try {
    while (sim.time() < r.end_time * (1 - 1e-14)) {
      const Real t0 = sim.time();
      sim.step(r.end_time - sim.time());
      if (sim.steps() == 1) r.dt = sim.time() - t0;
      if (o.error == ErrorMeasure::particles) {
        r.error.record(sim.particles(), sim.time(), exact);
      } else if constexpr (requires { sim.min_node_mass(); }) {
        if (sim.steps() > 1 || !halved_start)
          record_nodal_acceleration(r.error, sim.grid(), sim.min_node_mass(), t0, exact);
      }
    }
  } catch (const SimulationFailure& e) {
    r.ok = false;
    r.failure = e.what();
    r.error.linf = 1;
  }
  r.steps = sim.steps();
  if (final_state) *final_state = table_of(sim.particles(), exact, sim.time());
}

template <class Exact>
VerifyResult run_case(const Exact& exact, const VerifyOptions& o, ParticleTable* final_state) {
  constexpr int Dim = Exact::dim;
  if (!(o.amplitude < exact.max_amplitude()))
    throw InputError("--amplitude: expected A < " + std::to_string(exact.max_amplitude()) +
                     " (larger A inverts the material)");
  SimulationSpec<Dim> spec;
  exact.configure(spec, o.cells);
  spec.boundary.acceleration = o.constrained_acceleration;
  spec.kernel = o.kernel;
  spec.transfer = o.transfer;
  spec.integrator = o.integrator;
  spec.materials = {exact.mat};
  spec.cfl = o.cfl;
  if (o.cfl_speed == CflSpeed::reference) spec.dt = o.cfl * spec.h / exact.c();
  spec.half_step_velocity_given = o.start == HalfStepStart::exact;
  spec.body_force = [exact](const Vec<Dim>& X, Real t) { return exact.body_force(X, t); };

  // Reference lattice, then the exact state at t = 0: x = X + u, v, F (stress and volume follow from F); v at
  // t = -dt/2 for the exact half-step start.
  ParticleSet<Dim> p;
  exact.seed(p, spec.h / o.ppc);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] = p.X[i] + exact.displacement(p.X[i], 0);
    if constexpr (requires { Exact::periodic; })  // into the unit square the grid spans
      for (int d = 0; d < Dim; ++d) p.x[i][d] -= std::floor(p.x[i][d]);
    p.v[i] = exact.velocity(p.X[i], o.start == HalfStepStart::exact ? -spec.dt / 2 : 0);
    p.F[i] = exact.deformation_gradient(p.X[i], 0);
  }

  VerifyResult r;
  r.end_time = o.end_time > 0 ? o.end_time : exact.period();
  with_kernel<Dim>(o.kernel, [&]<class K>() {
    if (o.implicit) {
      ImplicitSimulation<Dim, K> sim(implicit_spec_of(spec, o.theta), std::move(p));
      return run_to_end(sim, exact, o, final_state, r);
    }
    Simulation<Dim, K> sim(spec, std::move(p));
    run_to_end(sim, exact, o, final_state, r);
  });
  return r;
}
}  // namespace

VerifyCase parse_case(std::string_view name) {
  for (std::size_t k = 0; k < case_names.size(); ++k)
    if (name == case_names[k]) return static_cast<VerifyCase>(k);
  throw InputError("case: unknown case '" + std::string(name) +
                   "' (expected axis-aligned, bar-1d, expanding-ring or shear-wave)");
}

std::string_view to_string(VerifyCase c) {
  return case_names[static_cast<std::size_t>(c)];
}

std::string_view integrator_name(const VerifyOptions& o) {
  return o.implicit ? "implicit" : to_string(o.integrator);
}

void set_integrator(VerifyOptions& o, std::string_view name, std::string_view key) {
  o.implicit = name == "implicit";
  if (o.implicit) return;
  try {
    o.integrator = parse_integrator(name, key);
  } catch (const InputError&) {
    throw InputError(std::string(key) + ": unknown name '" + std::string(name) +
                     "' (expected one of usf, usl, cd, musl, implicit)");
  }
}

int dimension(VerifyCase c, const VerifyOptions& o) {
  if (c == VerifyCase::bar_1d) return 1;
  return c == VerifyCase::axis_aligned && o.dim == 3 ? 3 : 2;
}

Real poisson_ratio(VerifyCase c, const VerifyOptions& o) {
  return o.poisson ? *o.poisson : (c == VerifyCase::axis_aligned || c == VerifyCase::shear_wave ? 0.3 : 0.0);
}

void validate(const VerifyOptions& o) {
  if (o.cells < 2) throw InputError("--cells: expected at least 2 cells per axis");
  if (o.poisson && !(*o.poisson >= 0 && *o.poisson < 0.5))
    throw InputError("--nu: expected a Poisson's ratio in [0, 0.5)");
  if (o.ppc < 1) throw InputError("--ppc: expected at least 1 particle per cell per axis");
  if (o.cfl_speed == CflSpeed::particles && !(o.cfl > 0 && o.cfl <= 1))
    throw InputError("--cfl: expected a number in (0, 1]");
  if (o.cfl_speed == CflSpeed::reference && !(o.cfl > 0 && o.cfl <= 2))
    throw InputError("--cfl: expected a number in (0, 2] with --cfl-speed reference");
  if (o.error == ErrorMeasure::nodal && o.implicit)
    throw InputError("--error nodal: the nodal acceleration is measured for the explicit integrators only");
  if (o.start == HalfStepStart::exact) {
    if (o.implicit || (o.integrator != Integrator::cd && o.integrator != Integrator::musl))
      throw InputError("--start exact: only centered difference (cd) and UVF-MPM (musl) start from v^{-1/2}");
    if (o.cfl_speed != CflSpeed::reference)
      throw InputError("--start exact: needs a fixed time step to place v^{-1/2} (--cfl-speed reference)");
  }
  if (o.constrained_acceleration == ConstrainedAcceleration::velocity_difference && o.implicit)
    throw InputError(
        "--constrained-acceleration: the implicit integrator solves for the end-of-step velocities and "
        "has no constrained acceleration to choose");
  if (!(o.amplitude >= 0)) throw InputError("--amplitude: expected a non-negative amplitude");
  if (!(o.end_time >= 0)) throw InputError("--end-time: expected a non-negative time (0: one period)");
  if (!(o.theta >= 0 && o.theta <= 1)) throw InputError("--theta: expected a number in [0, 1]");
}

VerifyResult verify(VerifyCase c, const VerifyOptions& o, ParticleTable* final_state) {
  validate(o);
  if (o.dim != 0 && o.dim != dimension(c, o))
    throw InputError("--dim: the " + std::string(to_string(c)) + " case is " +
                     (c == VerifyCase::axis_aligned ? std::string("2-D or 3-D")
                                                    : std::to_string(dimension(c, o)) + "-D only"));
  if (c != VerifyCase::axis_aligned && c != VerifyCase::shear_wave && o.poisson)
    throw InputError("--nu: the " + std::string(to_string(c)) +
                     " solution is written for nu = 0; only the "
                     "axis-aligned and shear-wave cases take --nu");
  switch (c) {
    case VerifyCase::bar_1d:
      return run_case(Bar1D{o.amplitude, NeoHookean::from_young_poisson(1e7, 0.0, 1000)}, o, final_state);
    case VerifyCase::expanding_ring:
      return run_case(ExpandingRing{o.amplitude, NeoHookean::from_young_poisson(1e7, 0.0, 1000)}, o,
                      final_state);
    case VerifyCase::axis_aligned:
    case VerifyCase::shear_wave:
      break;
  }
  const NeoHookean steel_like = NeoHookean::from_young_poisson(1e7, poisson_ratio(c, o), 1000);
  if (c == VerifyCase::shear_wave)
    return run_case(DiagonalShearWave{o.amplitude, steel_like}, o, final_state);
  if (o.dim == 3) return run_case(AxisAligned<3>{o.amplitude, steel_like}, o, final_state);
  return run_case(AxisAligned<2>{o.amplitude, steel_like}, o, final_state);
}

}  // namespace mpm

#pragma once
// The two engines a scene can run on, behind the one interface the run loop uses (SceneEngine,
// scene_engine.hpp): the explicit integrators (Wallstedt & Guilkey 2008) and the implicit step (Sulsky & Kaul
// 2004).
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/vtk.hpp"
#include "mpm/scene/build.hpp"
#include "run_arrays.hpp"
#include "scene_engine.hpp"
#include "scene_entry.hpp"

namespace mpm::scene_engines {

/// The engine checks the particles it is given (inside the grid, positive mass, GIMP sizes); name the scene.
template <class Make>
auto naming_scene(const Scene& sc, Make&& make) {
  try {
    return make();
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.rfind(sc.file.string(), 0) == 0) throw;
    throw InputError(sc.file.string() + ": " + what);
  }
}

/// What both adapters forward to their simulation alike: the step, the clock, the particles and grid, the
/// choices of the spec, and the constraints as history.csv reports them, in one order for both engines (the
/// grid's faces and regions, then the rigid bodies: their names, the forces they applied, their velocities at
/// t).
template <int Dim, class Spec, class Sim>
class SimulationAdapter : public SceneEngine<Dim> {
 public:
  void step(Real max_dt) override { sim_.step(max_dt); }
  Real time() const override { return sim_.time(); }
  std::int64_t steps() const override { return sim_.steps(); }
  Real next_dt() const override { return sim_.next_dt(); }
  ParticleSet<Dim>& particles() override { return sim_.particles(); }
  const ParticleSet<Dim>& particles() const override { return sim_.particles(); }
  const Grid<Dim>& grid() const override { return sim_.grid(); }
  const Outflow<Dim>& outflow() const override { return sim_.outflow(); }
  void restore_outflow(const Outflow<Dim>& out) override { sim_.restore_outflow(out); }
  void remove_outflow() override { sim_.remove_outflow(); }
  Transfer transfer() const override { return spec_.transfer; }
  KernelKind kernel() const override { return spec_.kernel; }
  std::vector<std::string> reaction_names() const override {
    std::vector<std::string> names = sim_.constraints().names();
    for (const RigidBody<Dim>& b : sim_.rigid_bodies().bodies()) names.push_back(b.name);
    return names;
  }
  std::vector<Vec<Dim>> reactions() const override {
    std::vector<Vec<Dim>> forces = sim_.face_reactions();
    const std::vector<Vec<Dim>> bodies = sim_.rigid_reactions();
    forces.insert(forces.end(), bodies.begin(), bodies.end());
    return forces;
  }
  std::vector<Vec<Dim>> reaction_velocities(Real t) const override {
    std::vector<Vec<Dim>> v = sim_.constraints().velocities(t);
    const std::vector<Vec<Dim>> bodies = sim_.rigid_bodies().velocities(t);
    v.insert(v.end(), bodies.begin(), bodies.end());
    return v;
  }

 protected:
  /// The spec, and the simulation make(spec_) builds from it (naming the scene in its errors).
  template <class Make>
  SimulationAdapter(const Scene& sc, Spec spec, Make&& make)
      : spec_(std::move(spec)), sim_(naming_scene(sc, [&] { return make(spec_); })) {}
  Spec spec_;
  Sim sim_;
};

/// The output fields of the rate-form state, and one for each internal variable the table's laws declare
/// (zero at the particles whose law does not declare it).
template <int Dim>
void add_state_fields(const std::vector<Material>& materials, const ParticleSet<Dim>& p,
                      std::vector<io::PointField>& fields) {
  const MaterialState& s = p.state;
  fields.push_back({"plastic_strain", 1, s.eps_bar});
  fields.push_back({"temperature_rise", 1, s.temperature});
  fields.push_back({"internal_energy", 1, s.energy});
  for (const DeclaredColumn& column : declared_columns(materials)) {
    std::vector<double> values(p.size(), 0.0);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (column.declared_by[p.material[i]]) values[i] = s.internal[i][column.column];
    fields.push_back({column.name, 1, std::move(values)});
  }
}
/// The rate-form state and the volumes in a checkpoint, and back.
template <int Dim>
void save_state(const ParticleSet<Dim>& p, io::CheckpointData& c) {
  const MaterialState& s = p.state;
  std::vector<double> sigma;
  for (const SymTensor<3>& t : s.sigma) sigma.insert(sigma.end(), t.c.begin(), t.c.end());
  c.reals["sigma"] = sigma;
  c.reals["eps_bar"] = s.eps_bar;
  c.reals["temperature"] = s.temperature;
  c.reals["energy"] = s.energy;
  c.reals["stretch3"] = s.stretch3;
  c.reals["V"] = p.V;
  c.row_widths.insert(
      {{"sigma", 6}, {"eps_bar", 1}, {"temperature", 1}, {"energy", 1}, {"stretch3", 1}, {"V", 1}});
  if (!s.keeps_internal) return;
  std::vector<double> internal;
  for (const InternalState& row : s.internal) internal.insert(internal.end(), row.begin(), row.end());
  c.reals["internal"] = internal;
  c.row_widths.insert({"internal", static_cast<std::int64_t>(internal_columns)});
}
template <int Dim>
void load_state(const io::CheckpointData& c, const std::string& where, ParticleSet<Dim>& p) {
  MaterialState& s = p.state;
  s.resize(p.size());
  const auto real = [&](const std::string& k) -> const std::vector<double>& {
    return entry(c.reals, k, where);
  };
  const std::vector<double>& sigma = real("sigma");
  if (sigma.size() != 6 * s.sigma.size()) throw InputError(where + ": array 'sigma' has the wrong size");
  for (std::size_t i = 0; i < s.sigma.size(); ++i)
    std::copy_n(sigma.begin() + 6 * i, 6, s.sigma[i].c.begin());
  for (auto [key, array] :
       {std::pair{"eps_bar", &s.eps_bar}, std::pair{"temperature", &s.temperature},
        std::pair{"energy", &s.energy}, std::pair{"stretch3", &s.stretch3}, std::pair{"V", &p.V}}) {
    if (real(key).size() != p.size()) throw InputError(where + ": array '" + key + "' has the wrong size");
    *array = real(key);
  }
  // The laws' internal variables, where the table's laws declare some (a checkpoint written before any law
  // declared them holds none: zero).
  if (const auto it = c.reals.find("internal"); s.keeps_internal && it != c.reals.end()) {
    if (it->second.size() != internal_columns * p.size())
      throw InputError(where + ": array 'internal' has the wrong size");
    for (std::size_t i = 0; i < p.size(); ++i)
      std::copy_n(it->second.begin() + static_cast<std::ptrdiff_t>(internal_columns * i), internal_columns,
                  s.internal[i].begin());
  }
}

/// Explicit USF/USL/CD/MUSL with any materials.
/// After a SimulationFailure, for the last state's frame: 1 for each particle that failed (the one of id
/// `named`, which the message names, and any with a non-finite position, velocity or F, det F <= 0, or
/// outside the grid), 0 for the others.
template <int Dim>
std::vector<double> failed_mask(const ParticleSet<Dim>& p, const GridGeometry<Dim>& g, std::int64_t named) {
  std::vector<double> mark(p.size(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Real J = p.F[i].determinant();
    const bool broken =
        !p.x[i].allFinite() || !p.v[i].allFinite() || !std::isfinite(J) || !(J > 0) || !g.contains(p.x[i]);
    if (broken || p.id[i] == named) mark[i] = 1;
  }
  return mark;
}

template <int Dim, class Kernel>
class Explicit final : public SimulationAdapter<Dim, SimulationSpec<Dim>, Simulation<Dim, Kernel>> {
  using SimulationAdapter<Dim, SimulationSpec<Dim>, Simulation<Dim, Kernel>>::spec_;
  using SimulationAdapter<Dim, SimulationSpec<Dim>, Simulation<Dim, Kernel>>::sim_;

 public:
  explicit Explicit(const Scene& sc)
      : SimulationAdapter<Dim, SimulationSpec<Dim>, Simulation<Dim, Kernel>>(
            sc, make_spec<Dim>(sc), [&](const SimulationSpec<Dim>& spec) {
              return Simulation<Dim, Kernel>(spec, seed_bodies<Dim>(sc), world());
            }) {}

  int velocity_fields() const override { return spec_.contact.fields; }
  /// After a SimulationFailure the particles hold the failed step's values.
  bool failure_keeps_state() const override { return false; }
  /// The power friction dissipated on the Coulomb walls in the last step [W].
  Real friction_power() const override { return sim_.friction_power(); }
  /// Stored energy V0 W(F) of a Neo-Hookean particle (the potential of Wallstedt & Guilkey 2008, Eq. (54)),
  /// the internal energy of a rate-form one (Sulsky & Kaul 2004, Eq. (2.2.16)).
  Real internal_energy(std::size_t i) const override { return sim_.internal_energy(i); }
  /// Each tile's particles in id order: the same bits for any division (Simulation::for_each_sum_run).
  void for_each_sum_run(const std::function<void(std::size_t, std::size_t)>& visit) const override {
    sim_.for_each_sum_run(visit);
  }
  const Communicator& communicator() const override { return sim_.communicator(); }
  /// This rank's particles' count, and all ranks'.
  std::int64_t particle_count() const override {
    std::vector<std::int64_t> n{static_cast<std::int64_t>(sim_.particles().size())};
    sim_.communicator().sum(n);
    return n[0];
  }
  /// The simulation accounts the loads' power itself (Simulation::load_power), as its particles move between
  /// ranks in a step: it needs no velocities from before the step.
  bool needs_velocities_before() const override { return false; }
  Real load_power(const std::vector<Vec<Dim>>&) const override { return sim_.load_power(); }
  /// Cauchy stress of particle i, xx yy zz xy yz xz (vtk_order); in 2-D a Neo-Hookean zz is the plane-strain
  /// lambda ln J / J (Wallstedt & Guilkey 2008, Eq. (55)).
  void stress(std::size_t i, double* out) const override { vtk_order(sim_.full_stress(i), out); }
  /// The rate-form state, and with [[contact]] each particle's velocity field (to tell the bodies apart).
  void add_fields(std::vector<io::PointField>& fields) const override {
    if (!sim_.particles().state.empty()) add_state_fields(spec_.materials, sim_.particles(), fields);
    if (spec_.contact.fields > 1) {
      const std::vector<std::uint16_t>& field = sim_.particles().field;
      fields.push_back(io::PointField{"field", 1, std::vector<double>(field.begin(), field.end())});
    }
  }
  void summarize(nlohmann::json&) const override {}
  /// newton.csv's rows: none for the explicit step.
  std::vector<NewtonAttempt> newton_attempts() const override { return {}; }
  /// history.csv's solver columns: none for the explicit step.
  std::vector<std::string> counter_names() const override { return {}; }
  std::vector<std::int64_t> counters() const override { return {}; }
  /// What each [[contact]] pair transmitted in the last step (Simulation::contact_forces).
  std::vector<PairForces<Dim>> contact_forces() const override { return sim_.contact_forces(); }
  /// The Coulomb walls' names and the spread of their normal force in the last step [m] (contact_spread).
  std::vector<std::string> spread_names() const override {
    std::vector<std::string> out;
    const std::vector<std::string> names = sim_.constraints().names();
    for (std::size_t g = 0; g < names.size(); ++g)
      if (sim_.constraints().coulomb(g)) out.push_back(names[g]);
    return out;
  }
  std::vector<Real> spreads() const override {
    std::vector<Real> out;
    if (spread_names().empty()) return out;  // no Coulomb wall: no sums to exchange between ranks
    const std::vector<Real> all = sim_.face_contact_spreads();
    for (std::size_t g = 0; g < all.size(); ++g)
      if (sim_.constraints().coulomb(g)) out.push_back(all[g]);
    return out;
  }
  void save(io::CheckpointData& c) const override {
    if (sim_.has_material_state()) save_state(sim_.particles(), c);
    if (!spec_.rigid_bodies.empty())
      c.reals["rigid_displacement"] = flat(sim_.rigid_bodies().displacements());
  }
  /// Without rate-form materials, volume and stress follow from F exactly as the step computes them
  /// (Wallstedt & Guilkey 2008, Eq. (13), Eq. (55)); with them, the checkpoint holds the state and the
  /// volumes.
  void load(const io::CheckpointData& c, const std::string& where) override {
    ParticleSet<Dim>& p = sim_.particles();
    const bool state = sim_.has_material_state();
    if (state) load_state(c, where, p);
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.material[i] >= spec_.materials.size())
        throw InputError(where + ": a particle's material has no entry");
      const Material& m = spec_.materials[p.material[i]];
      const Real J = p.F[i].determinant();
      if (!state) p.V[i] = p.V0[i] * J;
      if (!is_rate_form(m)) p.sigma[i] = std::get<NeoHookean>(m).template stress<Dim>(p.F[i], J);
    }
    if (!spec_.rigid_bodies.empty()) {
      std::vector<Vec<Dim>> rigid(spec_.rigid_bodies.size());
      unflat(entry(c.reals, "rigid_displacement", where), rigid, "rigid_displacement");
      sim_.restore_rigid_bodies(rigid);
    }
    sim_.restore_clock(entry(c.real_scalars, "time", where), entry(c.integer_scalars, "steps", where));
  }
  /// After every rank loaded its share: divide the grid by the particles and send each to its tile's owner.
  void take_particles() override { sim_.adopt_particles(); }
  /// After a SimulationFailure the particles hold the failed step's values: the particle the message names is
  /// marked, and any other that broke (failed_mask).
  std::vector<double> failed_particles() const override {
    return failed_mask(sim_.particles(), sim_.grid().geometry, sim_.failed_particle());
  }
};

/// The theta-blended implicit step with hypoelastic / von Mises materials and rigid bodies.
template <int Dim, class Kernel>
class Implicit final : public SimulationAdapter<Dim, ImplicitSpec<Dim>, ImplicitSimulation<Dim, Kernel>> {
  using SimulationAdapter<Dim, ImplicitSpec<Dim>, ImplicitSimulation<Dim, Kernel>>::spec_;
  using SimulationAdapter<Dim, ImplicitSpec<Dim>, ImplicitSimulation<Dim, Kernel>>::sim_;

 public:
  explicit Implicit(const Scene& sc)
      : SimulationAdapter<Dim, ImplicitSpec<Dim>, ImplicitSimulation<Dim, Kernel>>(
            sc, make_implicit_spec<Dim>(sc), [&](const ImplicitSpec<Dim>& spec) {
              if (world().size() > 1)
                throw InputError(
                    "simulation.integrator = \"implicit\": the implicit integrator runs in one process (its "
                    "distributed solver is a later step); start mpm without mpirun or srun");
              return ImplicitSimulation<Dim, Kernel>(spec, seed_bodies<Dim>(sc));
            }) {}

  /// The implicit step has one velocity field (the scene reader refuses [[contact]]).
  int velocity_fields() const override { return 1; }
  /// A step that fails (the solve, after every halving) leaves the particles at the last good state.
  bool failure_keeps_state() const override { return true; }
  /// Coulomb walls are refused for the implicit step (the scene reader): nothing dissipates there.
  Real friction_power() const override { return 0; }
  /// Internal energy e_p (Sulsky & Kaul 2004, Eq. (2.2.16)): stored plus dissipated; a Neo-Hookean particle's
  /// is its stored energy V0 W(F).
  Real internal_energy(std::size_t i) const override { return sim_.state().energy[i]; }
  /// The particles (one process) in storage order, one run.
  void for_each_sum_run(const std::function<void(std::size_t, std::size_t)>& visit) const override {
    visit(0, sim_.particles().size());
  }
  const Communicator& communicator() const override { return one_process(); }
  std::int64_t particle_count() const override { return static_cast<std::int64_t>(sim_.particles().size()); }
  void step(Real max_dt) override {
    const Real start = sim_.time();
    sim_.step(max_dt);
    step_dt_ = sim_.time() - start;
  }
  /// Power of gravity, the body force and the surface loads over the last step: sum_p m_p (g + b_p) .
  /// (v_before + v_after) / 2, plus the work of the surface loads' moments over the step's length.
  bool needs_velocities_before() const override { return true; }
  Real load_power(const std::vector<Vec<Dim>>& v_before) const override {
    const ParticleSet<Dim>& p = sim_.particles();
    return this->template particle_sum<1>([&](std::size_t i) {
      return std::array<Real, 1>{
          particle_load_power(p, i, spec_.gravity, sim_.body_acceleration(), v_before) +
          sim_.surface_loading().work(p, i, sim_.grid().geometry) / step_dt_};
    })[0];
  }
  void stress(std::size_t i, double* out) const override { vtk_order(sim_.state().sigma[i], out); }
  void add_fields(std::vector<io::PointField>& fields) const override {
    add_state_fields(spec_.materials, sim_.particles(), fields);
  }
  void summarize(nlohmann::json& j) const override {
    const ImplicitCounters& c = sim_.counters();
    j["implicit"] = {{"theta", spec_.theta},
                     {"formulation", to_string(spec_.formulation)},
                     {"positions", spec_.formulation == Formulation::velocity ? "velocity"
                                   : moves_with_projected_velocity(spec_)     ? "projected-velocity"
                                                                              : "momentum"},
                     {"solver", to_string(spec_.solver)},
                     {"preconditioner", spec_.frozen_jacobian ? "frozen-jacobian" : "none"},
                     {"preconditioner_builds", c.preconditioner_builds},
                     {"geometry", to_string(spec_.geometry)},
                     {"explicit_dt", sim_.explicit_dt()},
                     {"newton_iterations", c.newton_iterations},
                     {"krylov_iterations", c.krylov_iterations},
                     {"residual_evaluations", c.residual_evaluations},
                     {"line_search_backtracks", c.backtracks},
                     {"step_retries", c.retries}};
  }
  /// newton.csv's rows: the tries at the last step (after a failure, at the step that failed).
  std::vector<NewtonAttempt> newton_attempts() const override { return sim_.last_step_attempts(); }
  /// history.csv's solver columns: Newton and Krylov iterations since t = 0 (their differences per step draw
  /// Sulsky & Kaul 2004, Fig. 9a).
  /// The implicit step has one velocity field and no Coulomb walls (the scene reader refuses both).
  std::vector<PairForces<Dim>> contact_forces() const override { return {}; }
  std::vector<std::string> spread_names() const override { return {}; }
  std::vector<Real> spreads() const override { return {}; }
  std::vector<std::string> counter_names() const override {
    return {"newton_iterations", "krylov_iterations"};
  }
  std::vector<std::int64_t> counters() const override {
    return {sim_.counters().newton_iterations, sim_.counters().krylov_iterations};
  }
  void save(io::CheckpointData& c) const override {
    save_state(sim_.particles(), c);
    c.reals["rigid_displacement"] = flat(sim_.rigid_displacements());
    c.real_scalars["dt"] = sim_.next_dt();
    const ImplicitCounters& n = sim_.counters();
    c.integer_scalars["newton_iterations"] = n.newton_iterations;
    c.integer_scalars["krylov_iterations"] = n.krylov_iterations;
    c.integer_scalars["residual_evaluations"] = n.residual_evaluations;
    c.integer_scalars["backtracks"] = n.backtracks;
    c.integer_scalars["retries"] = n.retries;
    c.integer_scalars["preconditioner_builds"] = n.preconditioner_builds;
  }
  void load(const io::CheckpointData& c, const std::string& where) override {
    load_state(c, where, sim_.particles());
    std::vector<Vec<Dim>> rigid(spec_.rigid_bodies.size());
    unflat(entry(c.reals, "rigid_displacement", where), rigid, "rigid_displacement");
    const auto integer = [&](const std::string& k) { return entry(c.integer_scalars, k, where); };
    const ImplicitCounters n{
        integer("newton_iterations"), integer("krylov_iterations"), integer("residual_evaluations"),
        integer("backtracks"),        integer("retries"),           integer("preconditioner_builds")};
    sim_.restore(entry(c.real_scalars, "time", where), integer("steps"), entry(c.real_scalars, "dt", where),
                 n, rigid);
  }
  /// The implicit step runs in one process and locates its particles at every step: nothing to do.
  void take_particles() override {}
  /// A failed step leaves the last good state: no particle is marked unless that state broke (failed_mask).
  std::vector<double> failed_particles() const override {
    return failed_mask(sim_.particles(), sim_.grid().geometry, -1);
  }

 private:
  Real step_dt_ = 1;  ///< the last step's length (load_power)
};

}  // namespace mpm::scene_engines

namespace mpm {

template <int Dim, class Engine>
std::unique_ptr<SceneEngine<Dim>> make_engine(const Scene& sc) {
  return std::make_unique<Engine>(sc);
}

}  // namespace mpm

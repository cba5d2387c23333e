#pragma once
// The two engines a scene can run on, behind one small interface the scene runner uses: the explicit
// Neo-Hookean integrators (Wallstedt & Guilkey 2008) and the implicit rate-form step (Sulsky & Kaul 2004).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/integrators/simulation.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/vtk.hpp"
#include "mpm/scene/build.hpp"

namespace mpm::scene_engines {

template <class V>
std::vector<double> flat(const std::vector<V>& a) {
  std::vector<double> out;
  for (const V& v : a) out.insert(out.end(), v.data(), v.data() + v.size());
  return out;
}
template <class V>
void unflat(const std::vector<double>& in, std::vector<V>& a, const std::string& name) {
  const std::size_t per = static_cast<std::size_t>(V::SizeAtCompileTime);
  if (in.size() != a.size() * per) throw InputError("checkpoint: array '" + name + "' has the wrong size");
  for (std::size_t i = 0; i < a.size(); ++i) std::copy(in.begin() + i * per, in.begin() + (i + 1) * per, a[i].data());
}
template <class Map>
const auto& entry(const Map& map, const std::string& key, const std::string& where) {
  auto it = map.find(key);
  if (it == map.end()) throw InputError(where + ": not a checkpoint of this kind of run (no '" + key + "')");
  return it->second;
}

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

/// Explicit USF/USL/CD/MUSL with Neo-Hookean materials.
template <int Dim, class Kernel>
class Explicit {
 public:
  /// After a SimulationFailure the particles hold the failed step's values.
  static constexpr bool failure_keeps_state = false;

  explicit Explicit(const Scene& sc)
      : spec_(make_spec<Dim>(sc)),
        sim_(naming_scene(sc, [&] { return Simulation<Dim, Kernel>(spec_, seed_bodies<Dim>(sc)); })) {}

  Simulation<Dim, Kernel>& sim() { return sim_; }
  const Simulation<Dim, Kernel>& sim() const { return sim_; }
  std::vector<std::string> reaction_names() const { return sim_.constraints().names(); }
  std::vector<Vec<Dim>> reactions() const { return sim_.constraints().reactions(); }
  std::vector<Vec<Dim>> reaction_velocities(Real t) const { return sim_.constraints().velocities(t); }
  /// Stored energy sum_p V0 W(F) (Wallstedt & Guilkey 2008, Eq. 54's potential).
  Real strain_energy() const {
    const ParticleSet<Dim>& p = sim_.particles();
    Real e = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      e += p.V0[i] * spec_.materials[p.material[i]].template energy_density<Dim>(p.F[i], p.F[i].determinant());
    return e;
  }
  /// Acceleration of the external loads on particle i over the last step.
  Vec<Dim> load_acceleration(std::size_t i) const {
    const std::vector<Vec<Dim>>& b = sim_.body_acceleration();
    return b.empty() ? spec_.gravity : Vec<Dim>(spec_.gravity + b[i]);
  }
  /// Cauchy stress of particle i, xx yy zz xy xz yz; in 2-D zz is the plane-strain lambda ln J / J (Eq. 55).
  void stress(std::size_t i, double* out) const {
    static constexpr int voigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    const ParticleSet<Dim>& p = sim_.particles();
    const Real J = p.F[i].determinant();
    for (int k = 0; k < 6; ++k) {
      const int a = voigt[k][0], c = voigt[k][1];
      out[k] = (a < Dim && c < Dim) ? p.sigma[i](a, c)
               : a == c             ? spec_.materials[p.material[i]].lambda * std::log(J) / J
                                    : 0.0;
    }
  }
  void add_fields(std::vector<io::PointField>&) const {}
  void summarize(nlohmann::json&) const {}
  void save(io::CheckpointData&) const {}
  /// Volume and stress follow from F exactly as the step computes them (Eqs 13 and 55).
  void load(const io::CheckpointData& c, const std::string& where) {
    ParticleSet<Dim>& p = sim_.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Real J = p.F[i].determinant();
      p.V[i] = p.V0[i] * J;
      p.sigma[i] = spec_.materials.at(p.material[i]).template stress<Dim>(p.F[i], J);
    }
    sim_.restore_clock(entry(c.real_scalars, "time", where), entry(c.integer_scalars, "steps", where));
  }

 private:
  SimulationSpec<Dim> spec_;
  Simulation<Dim, Kernel> sim_;
};

/// The theta-blended implicit step with hypoelastic / von Mises materials and rigid bodies.
template <int Dim, class Kernel>
class Implicit {
 public:
  /// A step that fails (the solve, after every halving) leaves the particles at the last good state.
  static constexpr bool failure_keeps_state = true;

  explicit Implicit(const Scene& sc)
      : spec_(make_implicit_spec<Dim>(sc)),
        sim_(naming_scene(sc, [&] { return ImplicitSimulation<Dim, Kernel>(spec_, seed_bodies<Dim>(sc)); })) {}

  ImplicitSimulation<Dim, Kernel>& sim() { return sim_; }
  const ImplicitSimulation<Dim, Kernel>& sim() const { return sim_; }
  std::vector<std::string> reaction_names() const {
    std::vector<std::string> names = sim_.constraints().names();
    for (const RigidBody<Dim>& b : spec_.rigid_bodies) names.push_back(b.name);
    return names;
  }
  std::vector<Vec<Dim>> reactions() const {
    std::vector<Vec<Dim>> r = sim_.face_reactions();
    r.insert(r.end(), sim_.rigid_reactions().begin(), sim_.rigid_reactions().end());
    return r;
  }
  std::vector<Vec<Dim>> reaction_velocities(Real t) const {
    std::vector<Vec<Dim>> v = sim_.constraints().velocities(t);
    for (const RigidBody<Dim>& b : spec_.rigid_bodies) v.push_back(b.velocity(t));
    return v;
  }
  /// Internal energy sum_p e_p (Sulsky & Kaul 2004, Eq. 2.2.16): stored plus dissipated.
  Real strain_energy() const {
    Real e = 0;
    for (Real ep : sim_.state().energy) e += ep;
    return e;
  }
  Vec<Dim> load_acceleration(std::size_t) const { return spec_.gravity; }
  void stress(std::size_t i, double* out) const {
    const SymTensor<3>& s = sim_.state().sigma[i];
    for (int k = 0; k < 6; ++k) out[k] = s.c[k];
  }
  void add_fields(std::vector<io::PointField>& fields) const {
    const ElastoPlasticState& s = sim_.state();
    fields.push_back({"plastic_strain", 1, s.eps_bar});
    fields.push_back({"temperature_rise", 1, s.temperature});
    fields.push_back({"internal_energy", 1, s.energy});
  }
  void summarize(nlohmann::json& j) const {
    const ImplicitCounters& c = sim_.counters();
    j["implicit"] = {{"theta", spec_.theta},
                     {"formulation", to_string(spec_.formulation)},
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
  void save(io::CheckpointData& c) const {
    const ElastoPlasticState& s = sim_.state();
    std::vector<double> sigma;
    for (const SymTensor<3>& t : s.sigma) sigma.insert(sigma.end(), t.c.begin(), t.c.end());
    c.reals["sigma"] = sigma;
    c.reals["eps_bar"] = s.eps_bar;
    c.reals["temperature"] = s.temperature;
    c.reals["energy"] = s.energy;
    c.reals["stretch3"] = s.stretch3;
    c.reals["V"] = sim_.particles().V;
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
  void load(const io::CheckpointData& c, const std::string& where) {
    ElastoPlasticState& s = sim_.state();
    const auto real = [&](const std::string& k) -> const std::vector<double>& { return entry(c.reals, k, where); };
    const std::vector<double>& sigma = real("sigma");
    if (sigma.size() != 6 * s.sigma.size()) throw InputError(where + ": array 'sigma' has the wrong size");
    for (std::size_t i = 0; i < s.sigma.size(); ++i) std::copy_n(sigma.begin() + 6 * i, 6, s.sigma[i].c.begin());
    s.eps_bar = real("eps_bar");
    s.temperature = real("temperature");
    s.energy = real("energy");
    s.stretch3 = real("stretch3");
    sim_.particles().V = real("V");
    std::vector<Vec<Dim>> rigid(spec_.rigid_bodies.size());
    unflat(real("rigid_displacement"), rigid, "rigid_displacement");
    const auto integer = [&](const std::string& k) { return entry(c.integer_scalars, k, where); };
    const ImplicitCounters n{integer("newton_iterations"), integer("krylov_iterations"),
                             integer("residual_evaluations"), integer("backtracks"), integer("retries"), integer("preconditioner_builds")};
    sim_.restore(entry(c.real_scalars, "time", where), integer("steps"), entry(c.real_scalars, "dt", where), n, rigid);
  }

 private:
  ImplicitSpec<Dim> spec_;
  ImplicitSimulation<Dim, Kernel> sim_;
};

}  // namespace mpm::scene_engines

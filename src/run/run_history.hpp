#pragma once
// The columns of a scene run's history.csv.
#include <string>
#include <vector>

#include "mpm/scene/scene.hpp"
#include "run_units.hpp"
#include "scene_engine.hpp"

namespace mpm {

/// Whether a Coulomb wall or body dissipates energy by friction (history.csv's friction_dissipation).
inline bool has_friction(const Scene& sc) {
  for (const SceneFace& f : sc.faces)
    if (f.friction >= 0) return true;
  for (const SceneRigidBody& r : sc.rigid_bodies)
    if (r.friction >= 0) return true;
  return !sc.contacts.empty();
}
/// Whether material can leave through an outflow face (history.csv's outflow columns).
inline bool has_outflow(const Scene& sc) {
  for (const SceneFace& f : sc.faces)
    if (f.kind == SceneFace::Kind::outflow) return true;
  return false;
}

/// history.csv's columns with their units: the clock, energies, momentum, the constraints' reactions, the
/// engine's counters, the Coulomb walls' spreads, the contact pairs' forces, friction and outflow; energies,
/// momenta and forces per metre of thickness or per radian in 2-D (per_extent).
template <int Dim>
std::vector<HistoryColumn> history_columns(const Scene& sc, const SceneEngine<Dim>& engine) {
  static constexpr const char* axis[] = {"x", "y", "z"};
  const std::string per = per_extent<Dim>(sc.geometry), energy = "J" + per, force = "N" + per,
                    momentum = "kg*m/s" + per;
  std::vector<HistoryColumn> c{{"step", ""},
                               {"time", "s"},
                               {"kinetic_energy", energy},
                               {"internal_energy", energy},
                               {"total_energy", energy},
                               {"external_work", energy}};
  for (int d = 0; d < Dim; ++d) c.push_back({std::string("momentum_") + axis[d], momentum});
  for (const std::string& name : engine.reaction_names())
    for (int d = 0; d < Dim; ++d) c.push_back({"reaction_" + name + "_" + axis[d], force});
  for (const std::string& name : engine.counter_names()) c.push_back({name, ""});
  for (const std::string& name : engine.spread_names()) c.push_back({"contact_spread_" + name, "m"});
  for (std::size_t k = 0; k < sc.contacts.size(); ++k) {  // on the table's first group by its second
    const std::string pair = "contact" + std::to_string(k) + "_";
    for (int d = 0; d < Dim; ++d) c.push_back({pair + axis[d], force});
    c.push_back({pair + "normal", force});
    c.push_back({pair + "tangential", force});
  }
  if (has_friction(sc)) c.push_back({"friction_dissipation", energy});
  if (has_outflow(sc)) {
    c.push_back({"outflow_mass", "kg" + per});
    c.push_back({"outflow_energy", energy});
    for (int d = 0; d < Dim; ++d) c.push_back({std::string("outflow_momentum_") + axis[d], momentum});
  }
  return c;
}

/// history.csv's header line (history_columns' names).
template <int Dim>
std::string history_header(const Scene& sc, const SceneEngine<Dim>& engine) {
  std::string h;
  for (const HistoryColumn& column : history_columns(sc, engine)) h += (h.empty() ? "" : ",") + column.name;
  return h;
}

}  // namespace mpm

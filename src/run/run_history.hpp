#pragma once
// The columns of a scene run's history.csv.
#include <string>

#include "mpm/scene/scene.hpp"
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

/// history.csv's header: the clock, energies, momentum, the constraints' reactions, the engine's counters,
/// the Coulomb walls' spreads, the contact pairs' forces, friction and outflow.
template <int Dim>
std::string history_header(const Scene& sc, const SceneEngine<Dim>& engine) {
  static constexpr const char* axis[] = {"x", "y", "z"};
  std::string h = "step,time,kinetic_energy,internal_energy,total_energy,external_work";
  for (int d = 0; d < Dim; ++d) h += std::string(",momentum_") + axis[d];
  for (const std::string& name : engine.reaction_names())
    for (int d = 0; d < Dim; ++d) h += ",reaction_" + name + "_" + axis[d];
  for (const std::string& name : engine.counter_names()) h += ',' + name;
  for (const std::string& name : engine.spread_names()) h += ",contact_spread_" + name;
  for (std::size_t k = 0; k < sc.contacts.size(); ++k) {  // on the table's first group by its second
    const std::string pair = ",contact" + std::to_string(k) + "_";
    for (int d = 0; d < Dim; ++d) h += pair + axis[d];
    h += pair + "normal" + pair + "tangential";
  }
  if (has_friction(sc)) h += ",friction_dissipation";
  if (has_outflow(sc)) {
    h += ",outflow_mass,outflow_energy";
    for (int d = 0; d < Dim; ++d) h += std::string(",outflow_momentum_") + axis[d];
  }
  return h;
}

}  // namespace mpm

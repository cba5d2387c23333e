#pragma once
// The units of a scene run's outputs: what mass, volume, energy and force are per in 1-D and 2-D, and the
// units of history.csv's columns and summary.json's numbers (summary.json's `units`).
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "mpm/core/model_geometry.hpp"

namespace mpm {

/// What a particle's mass, volume and energy, and a force, are per in a scene of Dim dimensions: "" in 3-D,
/// "/m" (per metre of thickness) in plane strain and plane stress, "/rad" (per radian) in axisymmetry, "/m^2"
/// (per square metre of cross section) in 1-D.
template <int Dim>
std::string per_extent(Geometry geometry) {
  if constexpr (Dim == 3)
    return "";
  else if constexpr (Dim == 2)
    return geometry == Geometry::axisymmetric ? "/rad" : "/m";
  else
    return "/m^2";
}

/// One column of history.csv and its unit ("" for a count).
struct HistoryColumn {
  std::string name, unit;
};

/// The units of summary.json's numbers that have one, in the same nesting ({"time": "s", "energy":
/// {"kinetic": "J/m", ...}}), for those `summary` holds; extensive quantities per `extent` (per_extent).
inline nlohmann::json summary_units(const nlohmann::json& summary, const std::string& extent) {
  const std::string energy = "J" + extent;
  const std::vector<std::pair<const char*, std::string>> known{{"/time", "s"},
                                                               {"/end_time", "s"},
                                                               {"/wall_seconds", "s"},
                                                               {"/compute_seconds", "s"},
                                                               {"/memory/estimated_bytes", "B"},
                                                               {"/memory/peak_bytes", "B"},
                                                               {"/energy/kinetic", energy},
                                                               {"/energy/strain", energy},
                                                               {"/energy/external_work", energy},
                                                               {"/energy/friction_dissipation", energy},
                                                               {"/error/linf", "m"},
                                                               {"/error/l1", "m"},
                                                               {"/error/l2", "m"},
                                                               {"/settled/fraction", "1"},
                                                               {"/settled/largest_kinetic_energy", energy},
                                                               {"/settled/time", "s"},
                                                               {"/bounded_domains/first_time", "s"},
                                                               {"/outflow/mass", "kg" + extent},
                                                               {"/outflow/momentum", "kg*m/s" + extent},
                                                               {"/outflow/kinetic_energy", energy},
                                                               {"/outflow/internal_energy", energy},
                                                               {"/implicit/theta", "1"},
                                                               {"/implicit/explicit_dt", "s"}};
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [path, unit] : known) {
    const nlohmann::json::json_pointer at(path);
    if (summary.contains(at)) out[at] = unit;
  }
  return out;
}

}  // namespace mpm

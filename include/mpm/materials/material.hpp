#pragma once
/// The material interface both engines use. A material is a value type with its parameters: a hyperelastic
/// law gives the stress from F (NeoHookean), a rate-form law advances it from the velocity gradient over a
/// step (ElastoPlastic: hypoelastic or von Mises; the frictional DruckerPrager and MohrCoulomb; the
/// NewtonianFluid; ModifiedCamClay, which keeps an internal variable); the per-particle state of the
/// rate-form laws is a MaterialState owned by the particle set. Loops visit the variant once per particle or
/// take a lane policy when every material is of one kind (transfer/g2p_stress.hpp).
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/core/model_geometry.hpp"
#include "mpm/materials/cam_clay.hpp"
#include "mpm/materials/drucker_prager.hpp"
#include "mpm/materials/elastoplastic.hpp"
#include "mpm/materials/mohr_coulomb.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/materials/newtonian_fluid.hpp"
#include "mpm/materials/state.hpp"

namespace mpm {

using Material =
    std::variant<NeoHookean, ElastoPlastic, NewtonianFluid, DruckerPrager, MohrCoulomb, ModifiedCamClay>;

/// A law that keeps internal variables beyond the stress and the plastic strain: it names them
/// (`state_columns`, which reach the frames and checkpoints), gives their initial values at a stress (those a
/// particle file gives, NaN where it gives none, checked against the stress), a wave speed that
/// depends on the stress, its small-strain moduli at a reference state, and checks itself in a geometry
/// (cam_clay.hpp).
template <class Law>
concept DeclaresState = requires(const Law& law, const SymTensor<3>& sigma) {
  Law::state_columns;
  { law.initial_state(sigma, InternalState{}) } -> std::same_as<InternalState>;
  { law.wave_speed(Real{}, sigma) } -> std::same_as<Real>;
  { law.reference_lambda() } -> std::same_as<Real>;
  { law.reference_mu() } -> std::same_as<Real>;
};

/// The internal variables a law declares (none for the others).
template <class Law>
constexpr std::size_t state_column_count() {
  if constexpr (DeclaresState<Law>)
    return Law::state_columns.size();
  else
    return 0;
}
static_assert(
    []<class... Law>(std::variant<Law...>*) {
      return ((state_column_count<Law>() <= internal_columns) && ...);
    }(static_cast<Material*>(nullptr)),
    "a law declares more internal variables than InternalState holds: raise internal_columns (state.hpp)");

/// The laws of linear isotropic elasticity in rate form, whose wave speed follows the current density.
template <class Law>
concept HypoelasticLaw = std::is_same_v<Law, ElastoPlastic> || std::is_base_of_v<FrictionalSolid, Law>;

/// Whether a material's stress depends on the rate of deformation (and needs a MaterialState): every material
/// but the Neo-Hookean one.
inline bool is_rate_form(const Material& m) {
  return !std::holds_alternative<NeoHookean>(m);
}

/// Reference density rho0 [kg/m^3].
inline Real reference_density(const Material& m) {
  return std::visit([](const auto& law) { return law.rho0; }, m);
}

/// Dilatational wave speed at volume ratio J and Cauchy stress sigma [m/s] (only the laws of DeclaresState
/// read the stress).
inline Real wave_speed(const Material& m, Real J, const SymTensor<3>& sigma) {
  return std::visit(
      [&](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (HypoelasticLaw<Law>)
          return law.wave_speed(law.rho0 / J);
        else if constexpr (DeclaresState<Law>)
          return law.wave_speed(J, sigma);
        else
          return law.wave_speed(J);
      },
      m);
}

/// The wave speed at rest, for estimates made before a run: at J = 1 and, for the laws of DeclaresState, the
/// isotropic stress of their reference moduli [m/s].
inline Real wave_speed_at_rest(const Material& m) {
  return std::visit(
      [&](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (DeclaresState<Law>) {
          return std::sqrt((law.reference_lambda() + 2 * law.reference_mu()) / law.rho0);
        } else {
          return wave_speed(Material{law}, 1.0, SymTensor<3>{});
        }
      },
      m);
}

/// Young's modulus of the small-strain limit [Pa] (the implicit residual's scale; a fluid's bulk modulus).
inline Real young_modulus(const Material& m) {
  return std::visit(
      [](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (std::is_same_v<Law, NeoHookean>)
          return law.mu * (3 * law.lambda + 2 * law.mu) / (law.lambda + law.mu);
        else if constexpr (DeclaresState<Law>) {
          const Real lambda = law.reference_lambda(), mu = law.reference_mu();
          return mu * (3 * lambda + 2 * mu) / (lambda + mu);
        } else if constexpr (HypoelasticLaw<Law>)
          return law.E;
        else
          return law.bulk;
      },
      m);
}

/// The Lame constants of a material's small-strain limit [Pa] (a fluid: its bulk modulus and no shear
/// stiffness).
struct ElasticModuli {
  Real lambda, mu;
};
inline ElasticModuli small_strain_moduli(const Material& m) {
  return std::visit(
      [](const auto& law) -> ElasticModuli {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (std::is_same_v<Law, NeoHookean>)
          return {law.lambda, law.mu};
        else if constexpr (DeclaresState<Law>)
          return {law.reference_lambda(), law.reference_mu()};
        else if constexpr (HypoelasticLaw<Law>)
          return {law.lambda(), law.mu()};
        else
          return {law.bulk, 0};
      },
      m);
}

/// Check a material of a Dim-dimensional run in a geometry; throw InputError naming `where` ("materials[0]")
/// and what was expected.
inline void validate(const Material& m, const std::string& where, int dim, Geometry geometry) {
  if (const auto* law = std::get_if<ElastoPlastic>(&m)) return validate(*law, where);
  const bool declares_state = std::visit(
      [&](const auto& law) {
        if constexpr (DeclaresState<std::decay_t<decltype(law)>>) validate(law, where, geometry);
        return DeclaresState<std::decay_t<decltype(law)>>;
      },
      m);
  if (declares_state) return;
  const auto frictional = [&](const auto& law) {
    validate(law, where);
    if (geometry == Geometry::plane_stress)
      throw InputError(where +
                       ": Drucker-Prager and Mohr-Coulomb materials run in plane strain, axisymmetry or "
                       "3-D, not plane stress");
  };
  if (const auto* law = std::get_if<DruckerPrager>(&m)) return frictional(*law);
  if (const auto* law = std::get_if<MohrCoulomb>(&m)) return frictional(*law);
  if (const auto* fluid = std::get_if<NewtonianFluid>(&m)) {
    validate(*fluid, where);
    if (geometry != Geometry::plane_strain)
      throw InputError(where +
                       ": Newtonian fluids run in plane strain; plane stress and axisymmetry need a "
                       "hypoelastic or von-mises material");
    return;
  }
  const NeoHookean& law = std::get<NeoHookean>(m);
  if (!(law.rho0 > 0)) throw InputError(where + ".density: must be positive");
  if (!(law.mu > 0)) throw InputError(where + ": shear modulus must be positive (E > 0 and -1 < nu < 0.5)");
  if (!(law.lambda + 2.0 * law.mu / dim > 0 || dim == 1))
    throw InputError(where + ": bulk modulus must be positive (nu < 0.5)");
  if (geometry != Geometry::plane_strain)
    throw InputError(where +
                     ": Neo-Hookean materials run in plane strain; plane stress and axisymmetry need a "
                     "rate-form material (hypoelastic or von-mises)");
}

/// Keep the internal variables only where a law of the table declares some (MaterialState::keeps_internal),
/// and set each particle's to their initial values at its stress (zero for the laws that declare none),
/// taking those a particle file gave (s.internal, sized to the particles with NaN where not given) where its
/// law accepts them; throw InputError naming the particle's material (and the particle, for given values)
/// where its law cannot start so.
inline void start_internal_state(const std::vector<Material>& materials,
                                 const std::vector<std::uint16_t>& material, MaterialState& s) {
  s.keeps_internal = false;
  for (const Material& m : materials)
    s.keeps_internal =
        s.keeps_internal ||
        std::visit([](const auto& law) { return DeclaresState<std::decay_t<decltype(law)>>; }, m);
  std::vector<InternalState> given;
  if (s.internal.size() == s.sigma.size()) given = std::move(s.internal);
  s.internal.assign(s.keeps_internal ? s.sigma.size() : 0, InternalState{});
  for (std::size_t i = 0; i < s.internal.size(); ++i)
    std::visit(
        [&](const auto& law) {
          if constexpr (DeclaresState<std::decay_t<decltype(law)>>) {
            const InternalState& from_file = given.empty() ? unset_internal_state : given[i];
            try {
              s.internal[i] = law.initial_state(s.sigma[i], from_file);
            } catch (const InputError& e) {
              const bool file =
                  std::any_of(from_file.begin(), from_file.end(), [](Real v) { return v == v; });
              throw InputError(
                  "materials[" + std::to_string(material[i]) +
                  "]: " + (file ? "particle " + std::to_string(i) + " of a particle file: " : "") + e.what());
            }
          }
        },
        materials[material[i]]);
}

/// One internal variable in the frames: its column, its name and the laws that declare it there.
struct DeclaredColumn {
  std::size_t column;
  std::string name;
  std::string unit;               ///< StateColumn::unit
  std::vector<bool> declared_by;  ///< per material of the table
};

/// The internal variables the laws of a table declare, each name once (in the order of the table and the
/// columns).
inline std::vector<DeclaredColumn> declared_columns(const std::vector<Material>& materials) {
  std::vector<DeclaredColumn> out;
  for (std::size_t k = 0; k < materials.size(); ++k)
    std::visit(
        [&](const auto& law) {
          using Law = std::decay_t<decltype(law)>;
          if constexpr (DeclaresState<Law>)
            for (std::size_t c = 0; c < Law::state_columns.size(); ++c) {
              const std::string name = Law::state_columns[c].name;
              auto it = std::find_if(out.begin(), out.end(), [&](const DeclaredColumn& d) {
                return d.name == name && d.column == c;
              });
              if (it == out.end())
                it = out.insert(out.end(), {c, name, Law::state_columns[c].unit,
                                            std::vector<bool>(materials.size(), false)});
              it->declared_by[k] = true;
            }
        },
        materials[k]);
  return out;
}

/// Whether any material of a table is rate-form.
inline bool any_rate_form(const std::vector<Material>& materials) {
  for (const Material& m : materials)
    if (is_rate_form(m)) return true;
  return false;
}

/// The Neo-Hookean laws of a table whose materials are all Neo-Hookean (empty otherwise), for the lane path.
inline std::vector<NeoHookean> neo_hookean_only(const std::vector<Material>& materials) {
  std::vector<NeoHookean> out;
  for (const Material& m : materials) {
    if (is_rate_form(m)) return {};
    out.push_back(std::get<NeoHookean>(m));
  }
  return out;
}

}  // namespace mpm

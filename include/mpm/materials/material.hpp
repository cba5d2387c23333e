#pragma once
/// The material interface both engines use. A material is a value type with its parameters: a hyperelastic
/// law gives the stress from F (NeoHookean), a rate-form law advances it from the velocity gradient over a
/// step (ElastoPlastic: hypoelastic or von Mises; the frictional DruckerPrager and MohrCoulomb; the
/// NewtonianFluid); the per-particle state of the rate-form laws is a
/// MaterialState owned by the particle set. Loops visit the variant once per particle or take a lane policy
/// when every material is of one kind (transfer/g2p_stress.hpp).
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/core/model_geometry.hpp"
#include "mpm/materials/drucker_prager.hpp"
#include "mpm/materials/elastoplastic.hpp"
#include "mpm/materials/mohr_coulomb.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/materials/newtonian_fluid.hpp"

namespace mpm {

using Material = std::variant<NeoHookean, ElastoPlastic, NewtonianFluid, DruckerPrager, MohrCoulomb>;

/// The laws of linear isotropic elasticity in rate form, whose wave speed follows the current density.
template <class Law>
concept HypoelasticLaw = std::is_same_v<Law, ElastoPlastic> || std::is_base_of_v<FrictionalSolid, Law>;

/// Whether a material's stress depends on the rate of deformation (and needs a MaterialState): every material but
/// the Neo-Hookean one.
inline bool is_rate_form(const Material& m) { return !std::holds_alternative<NeoHookean>(m); }

/// Reference density rho0 [kg/m^3].
inline Real reference_density(const Material& m) {
  return std::visit([](const auto& law) { return law.rho0; }, m);
}

/// Dilatational wave speed at volume ratio J [m/s].
inline Real wave_speed(const Material& m, Real J) {
  return std::visit(
      [J](const auto& law) {
        if constexpr (HypoelasticLaw<std::decay_t<decltype(law)>>)
          return law.wave_speed(law.rho0 / J);
        else
          return law.wave_speed(J);
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
        else if constexpr (HypoelasticLaw<Law>)
          return law.E;
        else
          return law.bulk;
      },
      m);
}

/// The Lame constants of a material's small-strain limit [Pa] (a fluid: its bulk modulus and no shear stiffness).
struct ElasticModuli {
  Real lambda, mu;
};
inline ElasticModuli small_strain_moduli(const Material& m) {
  return std::visit(
      [](const auto& law) -> ElasticModuli {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (std::is_same_v<Law, NeoHookean>)
          return {law.lambda, law.mu};
        else if constexpr (HypoelasticLaw<Law>)
          return {law.lambda(), law.mu()};
        else
          return {law.bulk, 0};
      },
      m);
}

/// Check a material of a Dim-dimensional run in a geometry; throw InputError naming `where` ("materials[0]") and
/// what was expected.
inline void validate(const Material& m, const std::string& where, int dim, Geometry geometry) {
  if (const auto* law = std::get_if<ElastoPlastic>(&m)) return validate(*law, where);
  const auto frictional = [&](const auto& law) {
    validate(law, where);
    if (geometry == Geometry::plane_stress)
      throw InputError(where + ": Drucker-Prager and Mohr-Coulomb materials run in plane strain, axisymmetry or "
                               "3-D, not plane stress");
  };
  if (const auto* law = std::get_if<DruckerPrager>(&m)) return frictional(*law);
  if (const auto* law = std::get_if<MohrCoulomb>(&m)) return frictional(*law);
  if (const auto* fluid = std::get_if<NewtonianFluid>(&m)) {
    validate(*fluid, where);
    if (geometry != Geometry::plane_strain)
      throw InputError(where + ": Newtonian fluids run in plane strain; plane stress and axisymmetry need a "
                               "hypoelastic or von-mises material");
    return;
  }
  const NeoHookean& law = std::get<NeoHookean>(m);
  if (!(law.rho0 > 0)) throw InputError(where + ".density: must be positive");
  if (!(law.mu > 0)) throw InputError(where + ": shear modulus must be positive (E > 0 and -1 < nu < 0.5)");
  if (!(law.lambda + 2.0 * law.mu / dim > 0 || dim == 1))
    throw InputError(where + ": bulk modulus must be positive (nu < 0.5)");
  if (geometry != Geometry::plane_strain)
    throw InputError(where + ": Neo-Hookean materials run in plane strain; plane stress and axisymmetry need a "
                             "rate-form material (hypoelastic or von-mises)");
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

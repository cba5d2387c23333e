// Reading the [[materials]] tables of a scene: Neo-Hookean, rate-form (hypoelastic, von Mises), frictional
// (Drucker-Prager, Mohr-Coulomb) and Newtonian fluid.
#include <numbers>

#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// Run a validation that names its keys "law.KEY" and report a failure at the key as written in the file.
template <class Check>
void check_at_key(const Section& s, const Check& check) {
  try {
    check();
  } catch (const InputError& e) {  // "law.KEY: what"
    const std::string what = e.what();
    const std::size_t dot = what.find('.'), colon = what.find(": ");
    s.fail(what.substr(dot + 1, colon - dot - 1), what.substr(colon + 2));
  }
}

/// The keys of the frictional models, refused by the others.
constexpr const char* frictional_keys[] = {"cohesion", "friction_angle", "dilatancy_angle", "residual_cohesion",
                                           "residual_friction_angle", "residual_strain", "match", "tension_cutoff"};

/// Drucker-Prager or Mohr-Coulomb: E and nu, the strength (angles in degrees; the cohesions may be expressions of
/// the constants) and, for Drucker-Prager, the cone's match and the tension cut-off.
Material read_frictional(const Section& s, const Scene& sc, const std::string& model, double rho) {
  for (const char* k : {"lambda", "mu", "yield_strength", "hardening", "limit_strength", "softening",
                        "residual_strength", "specific_heat"})
    if (s.has(k)) s.fail(k, "does not apply to model = \"" + model + "\"");
  constexpr double degree = std::numbers::pi / 180;
  FrictionalSolid solid;
  for (const char* k : {"E", "nu"})
    if (!s.has(k)) s.fail(k, "missing (a number or an expression of the constants is required)");
  solid.E = s.constant_number("E", 0, sc.constants);
  solid.nu = s.constant_number("nu", 0, sc.constants);
  solid.rho0 = rho;
  FrictionalStrength& f = solid.strength;
  f.cohesion = s.constant_number("cohesion", 0, sc.constants);
  f.friction = s.constant_number("friction_angle", 0, sc.constants) * degree;
  f.dilatancy = s.constant_number("dilatancy_angle", 0, sc.constants) * degree;
  f.residual_strain = s.number("residual_strain", 0);
  f.residual_cohesion = s.constant_number("residual_cohesion", f.cohesion, sc.constants);
  f.residual_friction = s.constant_number("residual_friction_angle", f.friction / degree, sc.constants) * degree;
  if (model == "mohr-coulomb") {
    for (const char* k : {"match", "tension_cutoff"})
      if (s.has(k)) s.fail(k, "applies to model = \"drucker-prager\" only");
    MohrCoulomb law{solid};
    check_at_key(s, [&] { validate(law, "law"); });
    return law;
  }
  DruckerPrager law{solid};
  const std::string match = s.choice("match", "outer", {"outer", "inner", "plane-strain"});
  law.match = match == "outer" ? ConeMatch::outer : match == "inner" ? ConeMatch::inner : ConeMatch::plane_strain;
  law.tension = s.constant_number("tension_cutoff", std::numeric_limits<double>::infinity(), sc.constants);
  check_at_key(s, [&] { validate(law, "law"); });
  return law;
}
/// The rate-form laws of Sulsky & Kaul 2004: hypoelastic, or von Mises with the bilinear hardening law.
ElastoPlastic read_rate_form(const Section& s, const std::string& model, double rho) {
  for (const char* k : {"lambda", "mu"})
    if (s.has(k)) s.fail(k, "give E and nu for the " + model + " model");
  const double E = s.required_number("E"), nu = s.required_number("nu");
  if (!(E > 0)) s.fail("E", "expected a positive Young's modulus [Pa]");
  if (!(nu > -1 && nu < 0.5)) s.fail("nu", "expected a Poisson ratio in (-1, 0.5)");
  ElastoPlastic law;
  law.E = E;
  law.nu = nu;
  law.rho0 = rho;
  law.specific_heat = s.number("specific_heat", 0);
  if (law.specific_heat < 0) s.fail("specific_heat", "expected a non-negative specific heat [J/(kg K)]");
  law.plastic = model == "von-mises";
  if (law.plastic) {
    law.law.yield = s.required_number("yield_strength");
    law.law.hardening = s.number("hardening", 0);
    law.law.limit = s.number("limit_strength", std::numeric_limits<double>::infinity());
    law.law.softening = s.number("softening", 0);
    law.law.residual = s.number("residual_strength", 0);
    check_at_key(s, [&] { validate(law.law, "law"); });
  } else {
    for (const char* k : {"yield_strength", "hardening", "limit_strength", "softening", "residual_strength"})
      if (s.has(k)) s.fail(k, "applies to model = \"von-mises\" only");
  }
  return law;
}

/// The Newtonian fluid of Sulsky & Kaul 2004, Eq. (2.1.7).
NewtonianFluid read_fluid(const Section& s, const Scene& sc, double rho) {
  if (sc.geometry != Geometry::plane_strain)
    s.fail("model", "a Newtonian fluid runs in plane strain; plane stress and axisymmetry need model = "
                    "\"hypoelastic\" or \"von-mises\"");
  NewtonianFluid f;
  f.rho0 = rho;
  f.mu = s.required_number("viscosity");
  if (!(f.mu >= 0)) s.fail("viscosity", "expected a shear viscosity >= 0 [Pa s]");
  f.lambda = s.number("second_viscosity", -2 * f.mu / 3);
  if (!(3 * f.lambda + 2 * f.mu >= 0)) s.fail("second_viscosity", "expected lambda >= -2 mu / 3 [Pa s]");
  f.bulk = s.number("bulk_modulus", 0);
  if (!(f.bulk >= 0)) s.fail("bulk_modulus", "expected a bulk modulus >= 0 [Pa]");
  if (!(f.bulk > 0 || f.mu > 0)) s.fail("viscosity", "a fluid needs a viscosity or a bulk modulus > 0");
  return f;
}

/// The Neo-Hookean law from E and nu, or lambda and mu.
NeoHookean read_neo_hookean(const Section& s, const Scene& sc, double rho) {
  if (sc.geometry != Geometry::plane_strain)
    s.fail("model", "a Neo-Hookean material runs in plane strain; plane stress and axisymmetry need model = "
                    "\"hypoelastic\" or \"von-mises\"");
  const bool young = s.has("E") || s.has("nu"), lame = s.has("lambda") || s.has("mu");
  if (young == lame) s.fail(young ? "lambda" : "E", "give either E and nu, or lambda and mu");
  if (young) {
    const double E = s.required_number("E"), nu = s.required_number("nu");
    if (!(E > 0)) s.fail("E", "expected a positive Young's modulus [Pa]");
    if (!(nu > -1 && nu < 0.5)) s.fail("nu", "expected a Poisson ratio in (-1, 0.5)");
    return NeoHookean::from_young_poisson(E, nu, rho);
  }
  const double lambda = s.required_number("lambda"), mu = s.required_number("mu");
  if (!(mu > 0)) s.fail("mu", "expected a positive shear modulus [Pa]");
  if (!(lambda + 2 * mu / 3 > 0)) s.fail("lambda", "expected lambda + 2 mu / 3 > 0 (positive bulk modulus)");
  return NeoHookean{lambda, mu, rho};
}

}  // namespace

void read_material(const Section& s, Scene& sc) {
  SceneMaterial m;
  m.name = s.text("name", "");
  if (m.name.empty()) s.fail("name", "missing (each material needs a name bodies refer to)");
  for (const SceneMaterial& other : sc.materials)
    if (other.name == m.name) s.fail("name", "material '" + m.name + "' is defined twice");
  const std::string model =
      s.choice("model", "neo-hookean",
               {"neo-hookean", "hypoelastic", "von-mises", "newtonian-fluid", "drucker-prager", "mohr-coulomb"});
  const double rho = s.required_number("density");
  if (!(rho > 0)) s.fail("density", "expected a positive density [kg/m^3]");
  m.density = rho;
  const bool frictional = model == "drucker-prager" || model == "mohr-coulomb";
  if (!frictional)
    for (const char* k : frictional_keys)
      if (s.has(k)) s.fail(k, "applies to model = \"drucker-prager\" or \"mohr-coulomb\" only");
  if (frictional)
    m.law = read_frictional(s, sc, model, rho);
  else if (model == "neo-hookean")
    m.law = read_neo_hookean(s, sc, rho);
  else if (model == "newtonian-fluid")
    m.law = read_fluid(s, sc, rho);
  else
    m.law = read_rate_form(s, model, rho);
  sc.materials.push_back(m);
}

}  // namespace mpm::scene_reading

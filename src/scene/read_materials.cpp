// Reading the [[materials]] tables of a scene: Neo-Hookean, rate-form (hypoelastic, von Mises), frictional
// (Drucker-Prager, Mohr-Coulomb) and Newtonian fluid by readers of their own; the laws that declare their
// keys (modified Cam-Clay; materials/parameters.hpp) from their declarations.
#include <algorithm>
#include <iterator>
#include <numbers>
#include <utility>
#include <variant>
#include <vector>

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
constexpr const char* frictional_keys[] = {
    "cohesion",        "friction_angle", "dilatancy_angle", "residual_cohesion", "residual_friction_angle",
    "residual_strain", "match",          "tension_cutoff"};

/// Drucker-Prager or Mohr-Coulomb: E and nu, the strength (angles in degrees; the cohesions may be
/// expressions of the constants) and, for Drucker-Prager, the cone's match and the tension cut-off.
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
  f.residual_friction =
      s.constant_number("residual_friction_angle", f.friction / degree, sc.constants) * degree;
  if (model == "mohr-coulomb") {
    for (const char* k : {"match", "tension_cutoff"})
      if (s.has(k)) s.fail(k, "applies to model = \"drucker-prager\" only");
    MohrCoulomb law{solid};
    check_at_key(s, [&] { validate(law, "law"); });
    return law;
  }
  DruckerPrager law{solid};
  const std::string match = s.choice("match", "outer", {"outer", "inner", "plane-strain"});
  law.match = match == "outer"   ? ConeMatch::outer
              : match == "inner" ? ConeMatch::inner
                                 : ConeMatch::plane_strain;
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
    s.fail("model",
           "a Newtonian fluid runs in plane strain; plane stress and axisymmetry need model = "
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
    s.fail("model",
           "a Neo-Hookean material runs in plane strain; plane stress and axisymmetry need model = "
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

/// The law of `model` among the Material alternatives that declare their keys (DeclaresParameters), read from
/// them: each key as a number or an expression of the constants, then the law's own checks. False when no
/// such law has that name.
template <class... Law>
bool read_declared(const Section& s, const Scene& sc, const std::string& model, double rho, Material& out,
                   std::variant<Law...>*) {
  const auto one = [&]<class L>(L law) {
    if constexpr (DeclaresParameters<L>) {
      if (model != L::model) return false;
      law.rho0 = rho;
      for (const Parameter<L>& p : L::parameters()) {
        if (p.required && !s.has(p.key)) s.fail(p.key, std::string("missing: ") + p.what);
        law.*p.member = s.constant_number(p.key, p.fallback, sc.constants);
      }
      check_at_key(s, [&] { validate(Material{law}, "law", sc.dim, sc.geometry); });
      out = law;
      return true;
    }
    return false;
  };
  return (one(Law{}) || ...);
}

/// The keys of the laws that declare them, and which laws those are.
template <class... Law>
std::vector<std::pair<std::string, std::string>> declared_keys(std::variant<Law...>*) {
  std::vector<std::pair<std::string, std::string>> keys;  // key, model
  const auto one = [&]<class L>(L*) {
    if constexpr (DeclaresParameters<L>)
      for (const Parameter<L>& p : L::parameters()) keys.emplace_back(p.key, L::model);
  };
  (one(static_cast<Law*>(nullptr)), ...);
  return keys;
}

/// The names of the laws that declare their keys.
template <class... Law>
std::vector<std::string> declared_models(std::variant<Law...>*) {
  std::vector<std::string> models;
  const auto one = [&]<class L>(L*) {
    if constexpr (DeclaresParameters<L>) models.emplace_back(L::model);
  };
  (one(static_cast<Law*>(nullptr)), ...);
  return models;
}

constexpr Material* all_laws = nullptr;

/// The keys of the laws read by the readers above.
std::vector<std::string> keys_read_above() {
  std::vector<std::string> keys = {"name",
                                   "model",
                                   "E",
                                   "nu",
                                   "lambda",
                                   "mu",
                                   "density",
                                   "specific_heat",
                                   "yield_strength",
                                   "hardening",
                                   "limit_strength",
                                   "softening",
                                   "residual_strength",
                                   "viscosity",
                                   "second_viscosity",
                                   "bulk_modulus"};
  keys.insert(keys.end(), std::begin(frictional_keys), std::end(frictional_keys));
  return keys;
}
}  // namespace

std::vector<std::string> material_keys() {
  std::vector<std::string> keys = keys_read_above();
  for (const auto& [key, model] : declared_keys(all_laws))
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  return keys;
}

/// Every time step and budget divides by the wave speed at rest: refuse a law whose moduli overflow it (E
/// = 1.7e308 gives lambda + 2 mu = inf). The key named is the table's largest number, the modulus that
/// overflowed.
namespace {
void check_wave_speed(const Section& s, const Material& law) {
  const double c = wave_speed_at_rest(law);
  if (std::isfinite(c)) return;
  std::string largest = "density";
  double size = 0;
  for (const std::string& key : material_keys())
    if (const toml::node* n = s.get(key); n && n->is_number() && std::abs(number_value(*n)) > size) {
      size = std::abs(number_value(*n));
      largest = key;
    }
  s.fail(largest,
         "gives the material a wave speed at rest that is not a finite number (its moduli overflow); "
         "expected moduli below about 1e300 Pa");
}
}  // namespace

void read_material(const Section& s, Scene& sc) {
  SceneMaterial m;
  m.name = s.name("name", "");
  if (m.name.empty()) s.fail("name", "missing (each material needs a name bodies refer to)");
  for (const SceneMaterial& other : sc.materials)
    if (other.name == m.name) s.fail("name", "material '" + m.name + "' is defined twice");
  const std::vector<std::string> declared_names = declared_models(all_laws);
  std::vector<std::string> models = {"neo-hookean",     "hypoelastic",    "von-mises",
                                     "newtonian-fluid", "drucker-prager", "mohr-coulomb"};
  models.insert(models.end(), declared_names.begin(), declared_names.end());
  const std::string model = s.choice("model", "neo-hookean", models);
  const double rho = s.required_number("density");
  if (!(rho > 0)) s.fail("density", "expected a positive density [kg/m^3]");
  m.density = rho;
  // In the table of a law that declares its keys, any key but its own; in another, a key only such laws read.
  const std::vector<std::pair<std::string, std::string>> declared = declared_keys(all_laws);
  const std::vector<std::string> above = keys_read_above();
  const bool is_declared =
      std::find(declared_names.begin(), declared_names.end(), model) != declared_names.end();
  for (const std::string& key : material_keys()) {
    if (key == "name" || key == "model" || key == "density" || !s.has(key)) continue;
    const auto owner = [&](const std::string& law) {
      return std::find(declared.begin(), declared.end(), std::pair{key, law}) != declared.end();
    };
    if (is_declared && !owner(model)) s.fail(key, "does not apply to model = \"" + model + "\"");
    if (!is_declared && std::find(above.begin(), above.end(), key) == above.end()) {
      const auto d =
          std::find_if(declared.begin(), declared.end(), [&](const auto& x) { return x.first == key; });
      s.fail(key, "applies to model = \"" + d->second + "\" only");
    }
  }
  const bool frictional = model == "drucker-prager" || model == "mohr-coulomb";
  if (!frictional && !is_declared)
    for (const char* k : frictional_keys)
      if (s.has(k)) s.fail(k, "applies to model = \"drucker-prager\" or \"mohr-coulomb\" only");
  if (is_declared)
    read_declared(s, sc, model, rho, m.law, all_laws);
  else if (frictional)
    m.law = read_frictional(s, sc, model, rho);
  else if (model == "neo-hookean")
    m.law = read_neo_hookean(s, sc, rho);
  else if (model == "newtonian-fluid")
    m.law = read_fluid(s, sc, rho);
  else
    m.law = read_rate_form(s, model, rho);
  check_wave_speed(s, m.law);
  sc.materials.push_back(m);
}

}  // namespace mpm::scene_reading

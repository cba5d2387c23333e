#include "mpm/implicit/spec.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "mpm/core/errors.hpp"

namespace mpm {

namespace {
constexpr std::array<std::string_view, 3> geometry_names{"plane-strain", "plane-stress", "axisymmetric"};
constexpr std::array<std::string_view, 2> formulation_names{"velocity", "momentum"};
constexpr std::array<std::string_view, 4> solver_names{"newton-cg", "newton-gmres", "cg", "newton-direct"};
}  // namespace

Geometry parse_geometry(std::string_view name, std::string_view key) {
  return parse_name<Geometry>(geometry_names, name, key);
}
Formulation parse_formulation(std::string_view name, std::string_view key) {
  return parse_name<Formulation>(formulation_names, name, key);
}
ImplicitSolver parse_solver(std::string_view name, std::string_view key) {
  return parse_name<ImplicitSolver>(solver_names, name, key);
}
std::string_view to_string(Geometry g) {
  return geometry_names[static_cast<std::size_t>(g)];
}
std::string_view to_string(Formulation f) {
  return formulation_names[static_cast<std::size_t>(f)];
}
std::string_view to_string(ImplicitSolver s) {
  return solver_names[static_cast<std::size_t>(s)];
}

template <int Dim>
void validate(const ImplicitSpec<Dim>& s, const std::string& where) {
  const std::string at = where.empty() ? "" : where + ": ";
  validate_model<Dim>(s, at);
  for (const FaceCondition<Dim>& f : s.boundary.faces)
    require(!(f.friction >= 0), at + "grid.faces: Coulomb walls (friction) are for the explicit integrators");
  require(s.theta >= 0 && s.theta <= 1, at + "implicit.theta: expected a number in [0, 1]");
  require(s.transfer != Transfer::apic || !s.consistent_mass,
          at + "implicit.mass: APIC (transfer = \"apic\") runs with the lumped mass");
  require(s.solver != ImplicitSolver::linear_cg || s.formulation == Formulation::velocity,
          at + "implicit.solver: cg (linear) needs the symmetric velocity formulation");
  require(s.solver != ImplicitSolver::newton_cg || s.formulation == Formulation::velocity,
          at + "implicit.solver: newton-cg needs the symmetric velocity formulation (use newton-gmres)");
  require(!s.consistent_mass || s.formulation == Formulation::velocity,
          at + "implicit.mass: the consistent mass matrix needs the velocity formulation");
  require(!s.move_with_projected_velocity || s.formulation == Formulation::momentum,
          at + "implicit.positions: \"projected-velocity\" belongs to the momentum formulation (the velocity "
               "formulation moves the particles with its unknown v^L)");
  require(!s.consistent_mass || (!s.frozen_jacobian && s.solver != ImplicitSolver::newton_direct),
          at + "implicit.mass: the assembled Jacobians of the frozen-Jacobian preconditioner and "
               "newton-direct use the "
               "lumped mass");
  numerics::validate(s.newton, at + "[implicit]");
  const StepControl& c = s.step;
  if (c.dt > 0)
    require(std::isfinite(c.dt), at + "simulation.dt: must be finite");
  else
    require(c.dt == 0 && c.cfl > 0 && c.cfl <= 1, at + "simulation.cfl: expected a number in (0, 1]");
  require(std::isfinite(c.step_factor) && c.step_factor > 0, at + "implicit.step_factor: must be positive");
  require(std::isfinite(c.start_factor) && c.start_factor > 0,
          at + "implicit.start_factor: must be positive");
  require(c.growth >= 1 && std::isfinite(c.growth), at + "implicit.growth: expected a number >= 1");
  require(c.max_retries >= 0, at + "implicit.max_retries: expected an integer >= 0");
  require(
      s.theta > 0 || c.step_factor <= 1,
      at + "implicit.step_factor: theta = 0 is explicit and conditionally stable; expected step_factor <= 1");
  Real modulus = 0;
  for (const Material& m : s.materials) modulus = std::max(modulus, young_modulus(m));
  require(modulus > 0, at + "materials: the implicit residual is scaled by the stiffest material's modulus "
                            "(Sulsky & Kaul 2004, Sec. 3.2.2): give a fluid a bulk_modulus > 0");
  for (const RigidBody<Dim>& b : s.rigid_bodies)
    require(!(b.friction >= 0),
            at + "rigid body '" + b.name + "': Coulomb bodies are for the explicit integrators");
}

template void validate<1>(const ImplicitSpec<1>&, const std::string&);
template void validate<2>(const ImplicitSpec<2>&, const std::string&);
template void validate<3>(const ImplicitSpec<3>&, const std::string&);

}  // namespace mpm

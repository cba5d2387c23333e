#pragma once
/// Plain parameter structs of an implicit (or theta = 0 explicit) simulation in the formulation of Sulsky &
/// Kaul 2004, validated in full before anything is built.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/core/types.hpp"
#include "mpm/model/spec.hpp"
#include "mpm/numerics/newton_krylov.hpp"

namespace mpm {

/// The unknown of the implicit equations: nodal velocity (symmetric system, Sulsky & Kaul 2004, Eq. (2.4.11))
/// or nodal momentum (non-symmetric: Sulsky & Kaul 2004, Sec. 3.2.1, Eq. (3.2.3) to Eq. (3.2.7)).
enum class Formulation { velocity, momentum };

/// Newton-CG (Algs 1 and 3), Newton-GMRES (Algs 1 and 4), one linear CG solve (Alg. 2) of the system
/// linearised at the start of the step (exact for small-strain linear elasticity), or Newton with each step
/// solved directly by a sparse LU factorisation of the assembled Jacobian, rebuilt at every iterate (Alg. 1,
/// step 4 without a Krylov method).
enum class ImplicitSolver { newton_cg, newton_gmres, linear_cg, newton_direct };

/// The time step: the explicit reference step is cfl h / max_p (c_p + |v_p|) at t = 0 (or the fixed dt); the
/// step starts at start_factor times it and grows by `growth` per step up to step_factor times it (the
/// footnotes of Sulsky & Kaul 2004, Tables 1-6). A step whose Newton solve fails, or that would invert a
/// material point (the Lagrangian limit of Sec. 3.2.7), is retried with half the step up to max_retries
/// times.
struct StepControl {
  Real cfl = 0.5;         ///< Courant number of the explicit reference step
  Real dt = 0;            ///< fixed explicit reference step [s] instead of the CFL number (0: use cfl)
  Real step_factor = 1;   ///< target step / explicit step
  Real start_factor = 1;  ///< first step / explicit step (capped at step_factor)
  Real growth = 1.2;      ///< step ratio between consecutive steps while below the target
  int max_retries = 8;    ///< halvings allowed for one step
};

/// An implicit simulation: the model and the implicit step's settings.
template <int Dim>
struct ImplicitSpec : ModelSpec<Dim> {
  Formulation formulation = Formulation::momentum;
  ImplicitSolver solver = ImplicitSolver::newton_gmres;
  /// mu of Sulsky & Kaul 2004, Eq. (2.4.1): 0 explicit, 1 fully implicit.
  Real theta = 1;
  numerics::NewtonSettings newton;
  /// Precondition the Krylov solves with a sparse LU factorisation of the Jacobian, assembled by coloured
  /// forward differences and reused while the unknowns, the step and the Krylov counts stay the same (not in
  /// the paper).
  bool frozen_jacobian = false;
  /// Newton's residual divided by Y h^Dim dt, Y the largest Young's modulus (Sulsky & Kaul 2004, Sec. 3.2.2:
  /// the dimensionless form of its Newton-GMRES runs); false keeps it in force x time, as its Newton-CG runs
  /// (Tables 1-3), so that newton_tolerance is an absolute tolerance in those units.
  bool scaled_residual = true;
  /// The consistent mass matrix of Sulsky & Kaul 2004, Eq. (2.2.6) in the momentum equation and the
  /// projection, in place of the lumped one of Eq. (2.2.12) that the paper runs with (velocity formulation
  /// only).
  bool consistent_mass = false;
  /// Momentum formulation: move the particles with the velocity v^L projected from their updated velocities
  /// (Sulsky & Kaul 2004, Eq. (3.2.7)), the field whose gradient strains them, instead of with sum_i P_i^L
  /// N_i / m_i (Sulsky & Kaul 2004, Eq. (3.2.5)), the paper's position update, which moves them by a field
  /// their stress never sees, so that their positions drift from the deformation they record
  /// (docs/implicit.md, Sec. 7).
  bool move_with_projected_velocity = false;
  StepControl step;
};

/// Whether the momentum formulation moves the particles with v^L (Sulsky & Kaul 2004, Eq. (3.2.7)): when
/// asked, and always with CPDI2, whose corners, moved by the paper's sum_i P_i^L N_i / m_i, drift from the
/// deformation the stress resists until their domains fold (docs/kernels.md, CPDI2).
template <int Dim>
bool moves_with_projected_velocity(const ImplicitSpec<Dim>& s) {
  return s.formulation == Formulation::momentum &&
         (s.move_with_projected_velocity || s.kernel == KernelKind::cpdi2);
}

Formulation parse_formulation(std::string_view name, std::string_view key);
ImplicitSolver parse_solver(std::string_view name, std::string_view key);
std::string_view to_string(Formulation f);
std::string_view to_string(ImplicitSolver s);

/// Throw InputError with a clear message for the first invalid field; `where` prefixes every message.
template <int Dim>
void validate(const ImplicitSpec<Dim>& spec, const std::string& where = "");

}  // namespace mpm

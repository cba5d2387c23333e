#pragma once
/// A generic matrix-free Newton–Krylov solver for F(x) = 0 (Sulsky & Kaul 2004, Sec. 2.4): Newton's method
/// (Alg. 1) whose steps solve D_h F(x, s) = -F(x) (Eq. (2.4.19)) by CG (Alg. 3) or restarted GMRES(m)
/// (Alg. 4), with an optional backtracking line search (Sec. 3.2.3). The implicit MPM momentum residual is
/// one client; the solver knows nothing about MPM.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace mpm::numerics {

using Vector = Eigen::VectorXd;

/// A linear map out = A in (or a preconditioner out = P^{-1} in). An operator that cannot evaluate writes a
/// non-finite value into `out`; CG and GMRES then stop with the iterate built so far.
using LinearOperator = std::function<void(const Vector& in, Vector& out)>;

/// A nonlinear system F(x) = 0; the MPM momentum residual is one client.
class NonlinearProblem {
 public:
  virtual ~NonlinearProblem() = default;
  /// Number of unknowns (and of residual components).
  virtual Eigen::Index size() const = 0;
  /// r = F(x); r arrives sized size(). Returns false when F cannot be evaluated at x (e.g. a material point
  /// would invert): a failed trial point makes the line search back off, a failed iterate stops the solve.
  virtual bool residual(const Vector& x, Vector& r) = 0;
  /// Optional exact Jacobian-vector product Js = J(x) s; returns false when not provided (the default).
  virtual bool jacobian_vector(const Vector& /*x*/, const Vector& /*s*/, Vector& /*Js*/) { return false; }
  /// Optional preconditioner z = P^{-1} r (e.g. Jacobi); returns false when not provided (the default).
  virtual bool precondition(const Vector& /*r*/, Vector& /*z*/) { return false; }
  /// Optional: rebuild the preconditioner at x, where F(x) = fx (see NewtonSettings::refresh_after). Returns
  /// false when that failed; the solve then goes on with the old one.
  virtual bool refresh_preconditioner(const Vector& /*x*/, const Vector& /*fx*/) { return false; }
};

/// The solver of the Newton step's linear system (Alg. 1, step 4): a Krylov method, or `direct`, the
/// problem's preconditioner taken as an exact factorisation of the Jacobian and rebuilt at every iterate
/// (needs precondition; Sulsky & Kaul 2004, Alg. 1 allows any solver of step 4).
enum class Krylov { cg, gmres, direct };

/// How the linear tolerance gamma (the forcing term) is chosen at each Newton step.
enum class Forcing { constant, eisenstat_walker };

/// Parameters of solve(); the names are the scene-file keys (Sulsky & Kaul 2004, Sec. 3.2.2).
struct NewtonSettings {
  Krylov krylov = Krylov::gmres;
  /// epsilon: converged when ||F(x)||_2 <= epsilon (absolute, Alg. 1 step 2).
  double newton_tolerance = 1e-5;
  /// gamma in (0, 1): Krylov stops when ||J s + F||_2 <= gamma ||F(x)||_2; with Eisenstat–Walker forcing it
  /// is the first forcing term and the cap eta_max.
  double linear_tolerance = 1e-3;
  double derivative_step = 1e-5;        ///< h of Sulsky & Kaul 2004, Eq. (2.4.18)
  int restart = 20;                     ///< GMRES(m) restart length m
  int max_newton = 50;                  ///< Newton iterations before giving up
  int max_krylov = 500;                 ///< Krylov iterations per Newton step (over all restarts)
  bool line_search = true;              ///< Armijo backtracking on ||F|| (Sec. 3.2.3)
  int max_backtracks = 10;              ///< step halvings per Newton step before the line search fails
  Forcing forcing = Forcing::constant;  ///< constant gamma, or Eisenstat–Walker choice 2 capped at gamma
  bool exact_jacobian = false;  ///< problem.jacobian_vector instead of Sulsky & Kaul 2004, Eq. (2.4.18)
                                ///< (InputError if absent)
  bool precondition = false;    ///< use problem.precondition (InputError if absent)
  /// With precondition: after a linear solve that needed more than this many iterations, the next Newton
  /// iterate calls problem.refresh_preconditioner (a lagged Jacobian preconditioner); 0 never refreshes.
  int refresh_after = 8;
};

/// Throws mpm::InputError naming `where` and the key of the first impossible setting, e.g.
/// "scene.toml: [implicit] restart: expected an integer >= 1, got 0".
void validate(const NewtonSettings& s, const std::string& where);

/// What solve() did.
struct SolveStats {
  bool converged = false;
  int newton_iterations = 0;     ///< accepted Newton steps
  int krylov_iterations = 0;     ///< operator applications inside CG/GMRES, over all Newton steps
  int residual_evaluations = 0;  ///< every call of problem.residual, including D_h F and line search
  int jacobian_products = 0;     ///< exact products when exact_jacobian
  int backtracks = 0;            ///< step halvings in the line search
  int derivative_failures = 0;   ///< D_h F evaluations whose perturbed residual failed (Krylov cut short)
  int refreshes = 0;             ///< preconditioner rebuilds asked of the problem (refresh_after)
  std::vector<double> residual_norms;  ///< ||F(x_n)||_2 for n = 0, 1, ...
  std::string failure;                 ///< why it stopped without converging (empty when converged)
};

/// Solves F(x) = 0 from the initial guess in x, leaving the last iterate there. Throws mpm::InputError for
/// invalid settings only; non-convergence is reported in SolveStats. A caller that has already evaluated F at
/// the initial guess passes it as `residual_at_x`, which saves (and does not count) that evaluation.
SolveStats solve(NonlinearProblem& problem, Vector& x, const NewtonSettings& settings,
                 const Vector* residual_at_x = nullptr);

/// The forward difference D_h F(x, s) of Sulsky & Kaul 2004, Eq. (2.4.18) given Fx = F(x); false if F fails
/// at the perturbed point.
bool directional_derivative(NonlinearProblem& problem, const Vector& x, const Vector& Fx, const Vector& s,
                            double h, Vector& out);
/// As above, with `point` as caller-owned scratch for the perturbed point (no allocation once sized).
bool directional_derivative(NonlinearProblem& problem, const Vector& x, const Vector& Fx, const Vector& s,
                            double h, Vector& out, Vector& point);

/// Outcome of a linear Krylov solve.
struct LinearStats {
  bool converged = false;
  int iterations = 0;          ///< operator applications for search directions / basis vectors
  double residual_norm = 0.0;  ///< ||b - A x||_2 (CG: recursive; GMRES: the Arnoldi estimate |g_{k+1}|)
};

/// Preconditioned CG (Alg. 2, first direction normalised as in Alg. 3) for SPD A from the guess in x (zero if
/// x is empty); stops when ||r|| <= tolerance ||b||, after max_iterations, or on breakdown (p^T A p <= 0 or
/// non-finite).
LinearStats conjugate_gradient(const LinearOperator& apply, const Vector& b, Vector& x, double tolerance,
                               int max_iterations, const LinearOperator& precondition = {});

/// Restarted GMRES(m) (Alg. 4: modified Gram–Schmidt Arnoldi, Givens rotations), right-preconditioned;
/// same stopping rule, max_iterations counted over all restarts.
LinearStats gmres(const LinearOperator& apply, const Vector& b, Vector& x, double tolerance, int restart,
                  int max_iterations, const LinearOperator& precondition = {});

}  // namespace mpm::numerics

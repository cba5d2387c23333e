// Matrix-free Newton–Krylov (Sulsky & Kaul 2004, Sec. 2.4; Kelley 1995, Chs. 2, 3, 6 and 8).
#include "mpm/numerics/newton_krylov.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "mpm/core/errors.hpp"

namespace mpm::numerics {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// ---- settings -------------------------------------------------------------------------------------------

std::string key_path(const std::string& where, const char* key) {
  return where.empty() ? std::string(key) : where + " " + key;
}

template <class T>
[[noreturn]] void reject(const std::string& where, const char* key, const char* expected, T got) {
  std::ostringstream os;
  os << key_path(where, key) << ": expected " << expected << ", got " << got;
  throw InputError(os.str());
}

void require_positive(double value, const std::string& where, const char* key) {
  if (!(value > 0 && std::isfinite(value))) reject(where, key, "a finite number > 0", value);
}

void require_at_least(int value, int least, const std::string& where, const char* key) {
  if (value >= least) return;
  reject(where, key, least == 0 ? "an integer >= 0" : "an integer >= 1", value);
}

// ---- linear Krylov solvers ------------------------------------------------------------------------------

// r = b - A x, without a product when x = 0 (the Newton steps start from s_0 = 0, r_0 = -F; Alg. 3 and 4).
void initial_residual(const LinearOperator& apply, const Vector& b, const Vector& x, Vector& r) {
  if (x.isZero(0.0)) {
    r = b;
    return;
  }
  apply(x, r);
  r = b - r;
}

// Workspace and steps of one GMRES(m) call, allocated once: the basis p_1..p_{m+1}, the Hessenberg matrix
// (reduced in place to R by Givens rotations), the rotations and the rotated right-hand side beta e_1.
class Gmres {
 public:
  Gmres(Eigen::Index n, int m, const LinearOperator& apply, const LinearOperator& precondition)
      : apply_(apply),
        precondition_(precondition),
        v_(static_cast<std::size_t>(m) + 1, Vector(n)),
        h_(m + 1, m),
        c_(m),
        s_(m),
        g_(m + 1),
        y_(m),
        w_(n),
        z_(precondition ? n : 0) {}

  Vector& start_vector() { return basis(0); }

  // One restart cycle from the residual in start_vector() with norm beta: Arnoldi steps until |g_{k+1}| <=
  // target, m steps or the iteration budget; then x += P^{-1} V_k y. Returns false on a breakdown.
  bool cycle(double beta, double target, int budget, Vector& x, LinearStats& stats) {
    // Sulsky & Kaul 2004, Alg. 4, step 1: p_1 = r_0 / ||r_0||, beta e_1
    v_[0] /= beta;
    g_.setZero();
    g_(0) = beta;
    int k = 0;
    bool ok = true;
    while (k < h_.cols() && stats.iterations < budget && std::abs(g_(k)) > target) {
      ++stats.iterations;
      if (!(ok = extend(k))) break;
      ++k;
    }
    correct(k, x);
    stats.residual_norm = std::abs(g_(k));  // Alg. 4, step 2(g): |g_{k+1}| is ||b - A x||
    return ok;
  }

 private:
  Vector& basis(int i) { return v_[static_cast<std::size_t>(i)]; }

  // Alg. 4, step 2(a)-(g) for column k (0-based); false when the operator failed or A P^{-1} p_k = 0.
  bool extend(int k) {
    // (a) p_{k+1} = A P^{-1} p_k (right preconditioning)
    if (precondition_) precondition_(basis(k), z_);
    apply_(precondition_ ? z_ : basis(k), w_);
    // (b)-(c) modified Gram-Schmidt
    for (int i = 0; i <= k; ++i) {
      h_(i, k) = w_.dot(basis(i));
      w_ -= h_(i, k) * basis(i);
    }
    const double h_next = w_.norm();
    if (!std::isfinite(h_next)) return false;
    // (e) the previous rotations on column k
    for (int i = 0; i < k; ++i) {
      const double t = c_(i) * h_(i, k) + s_(i) * h_(i + 1, k);
      h_(i + 1, k) = -s_(i) * h_(i, k) + c_(i) * h_(i + 1, k);
      h_(i, k) = t;
    }
    // (f) the rotation eliminating h_{k+1,k}
    const double r = std::hypot(h_(k, k), h_next);
    if (r == 0) return false;
    c_(k) = h_(k, k) / r;
    s_(k) = h_next / r;
    h_(k, k) = r;
    h_(k + 1, k) = 0;
    // (g) rotate beta e_1
    g_(k + 1) = -s_(k) * g_(k);
    g_(k) *= c_(k);
    // (d) normalise (h_next = 0 is the lucky breakdown: |g_{k+1}| = 0 and the next basis vector is unused)
    if (h_next > 0) basis(k + 1) = w_ / h_next;
    return true;
  }

  // Alg. 4, steps 3-4: solve R y = g, then x += P^{-1} (y_1 p_1 + ... + y_k p_k).
  void correct(int k, Vector& x) {
    if (k == 0) return;
    y_.head(k) = g_.head(k);
    h_.topLeftCorner(k, k).triangularView<Eigen::Upper>().solveInPlace(y_.head(k));
    w_ = y_(0) * basis(0);
    for (int i = 1; i < k; ++i) w_ += y_(i) * basis(i);
    if (!precondition_) {
      x += w_;
      return;
    }
    precondition_(w_, z_);
    x += z_;
  }

  const LinearOperator& apply_;
  const LinearOperator& precondition_;
  std::vector<Vector> v_;
  Eigen::MatrixXd h_;
  Vector c_, s_, g_, y_, w_, z_;
};

// ---- Newton ---------------------------------------------------------------------------------------------

// Forwards to a problem, counting every residual evaluation.
class CountedProblem final : public NonlinearProblem {
 public:
  CountedProblem(NonlinearProblem& inner, int& count) : inner_(inner), count_(count) {}
  Eigen::Index size() const override { return inner_.size(); }
  bool residual(const Vector& x, Vector& r) override {
    ++count_;
    return inner_.residual(x, r);
  }

 private:
  NonlinearProblem& inner_;
  int& count_;
};

class Newton {
 public:
  Newton(NonlinearProblem& problem, Vector& x, const NewtonSettings& settings)
      : problem_(problem),
        counted_(problem, stats_.residual_evaluations),
        x_(x),
        settings_(settings),
        fx_(x.size()),
        s_(x.size()),
        rhs_(x.size()),
        trial_(x.size()),
        f_trial_(x.size()),
        point_(x.size()) {}

  // Sulsky & Kaul 2004, Alg. 1.
  SolveStats run(const Vector* residual_at_x) {
    if (residual_at_x)
      fx_ = *residual_at_x;
    else if (!counted_.residual(x_, fx_))
      return fail("F cannot be evaluated at the initial guess");
    norm_ = fx_.norm();
    stats_.residual_norms.push_back(norm_);
    double eta = settings_.linear_tolerance;
    while (true) {
      if (!std::isfinite(norm_)) return fail("non-finite residual norm");
      // Step 2: ||F(x_n)||_2 <= epsilon
      if (norm_ <= settings_.newton_tolerance) {
        stats_.converged = true;
        return stats_;
      }
      if (stats_.newton_iterations == settings_.max_newton) return fail(no_convergence());
      // Steps 3-4: D_h F(x_n, s) = -F(x_n), Sulsky & Kaul 2004, Eq. (2.4.19)
      if (refresh_) {
        ++stats_.refreshes;
        problem_.refresh_preconditioner(x_, fx_);
        refresh_ = false;
      }
      krylov_step(eta);
      refresh_ =
          refresh_ || settings_.krylov == Krylov::direct;  // the next iterate gets its own factorisation
      if (s_.isZero(0.0)) return fail("the Krylov solve produced no step (J s = 0, or D_h F failed)");
      // Step 5: x_{n+1} = x_n + lambda s
      const double norm_old = norm_;
      if (!advance()) return stats_;
      ++stats_.newton_iterations;
      stats_.residual_norms.push_back(norm_);
      if (settings_.forcing == Forcing::eisenstat_walker) eta = forcing(eta, norm_old);
    }
  }

 private:
  SolveStats fail(std::string why) {
    give_up(std::move(why));
    return stats_;
  }

  bool give_up(std::string why) {
    stats_.failure = std::move(why);
    return false;
  }

  std::string no_convergence() const {
    std::ostringstream os;
    os << "no convergence in " << settings_.max_newton << " Newton iterations (||F|| = " << std::scientific
       << std::setprecision(3) << norm_ << ")";
    return os.str();
  }

  // s such that ||D_h F(x, s) + F(x)|| <= eta ||F(x)||, from s_0 = 0 (Alg. 3 or 4, step 1).
  void krylov_step(double eta) {
    rhs_ = -fx_;
    s_.setZero();
    if (settings_.krylov == Krylov::direct) {
      apply_preconditioner(rhs_, s_);
      return;
    }
    const LinearOperator apply = [this](const Vector& p, Vector& jp) { apply_jacobian(p, jp); };
    LinearOperator precondition;
    if (settings_.precondition)
      precondition = [this](const Vector& r, Vector& z) { apply_preconditioner(r, z); };
    const LinearStats linear =
        settings_.krylov == Krylov::cg
            ? conjugate_gradient(apply, rhs_, s_, eta, settings_.max_krylov, precondition)
            : gmres(apply, rhs_, s_, eta, settings_.restart, settings_.max_krylov, precondition);
    stats_.krylov_iterations += linear.iterations;
    refresh_ =
        settings_.precondition && settings_.refresh_after > 0 && linear.iterations > settings_.refresh_after;
  }

  // J(x) p exactly, or by Sulsky & Kaul 2004, Eq. (2.4.18); a failed difference writes NaN so the Krylov
  // solve stops there.
  void apply_jacobian(const Vector& p, Vector& jp) {
    if (settings_.exact_jacobian) {
      if (!problem_.jacobian_vector(x_, p, jp))
        throw InputError("exact_jacobian = true, but the problem provides no Jacobian-vector product");
      ++stats_.jacobian_products;
      return;
    }
    if (directional_derivative(counted_, x_, fx_, p, settings_.derivative_step, jp, point_)) return;
    ++stats_.derivative_failures;
    jp.setConstant(nan);
  }

  void apply_preconditioner(const Vector& r, Vector& z) {
    if (!problem_.precondition(r, z))
      throw InputError("precondition = true, but the problem provides no preconditioner");
  }

  // x += lambda s with lambda = 1, 1/2, 1/4, ... until the Armijo condition
  // ||F(x + lambda s)|| <= (1 - 1e-4 lambda) ||F(x)|| holds (Sulsky & Kaul 2004, Sec. 3.2.3; Kelley 1995,
  // Ch. 8), or the full step without a line search. False (with the reason recorded) when that fails.
  bool advance() {
    constexpr double alpha = 1e-4;  // Kelley 1995, Ch. 8
    double lambda = 1, norm = nan;
    for (int halvings = 0;; ++halvings) {
      trial_ = x_ + lambda * s_;
      const bool ok = counted_.residual(trial_, f_trial_);
      norm = ok ? f_trial_.norm() : nan;
      if (!settings_.line_search && !ok) return give_up("F cannot be evaluated at the Newton step");
      if (!settings_.line_search || norm <= (1 - alpha * lambda) * norm_) break;
      if (halvings == settings_.max_backtracks) return give_up(line_search_failure());
      lambda /= 2;
      ++stats_.backtracks;
    }
    x_.swap(trial_);
    fx_.swap(f_trial_);
    norm_ = norm;
    return true;
  }

  std::string line_search_failure() const {
    std::ostringstream os;
    os << "line search failed: no sufficient decrease after " << settings_.max_backtracks
       << " step halvings (||F|| = " << std::scientific << std::setprecision(3) << norm_ << ")";
    return os.str();
  }

  // Eisenstat & Walker 1996, choice 2 with gamma = 0.9, alpha = 2, and the safeguards of Kelley 1995,
  // Ch. 6: keep eta large while the previous one was (gamma eta^2 > 0.1), cap it at eta_max =
  // linear_tolerance, and do not oversolve the last step (eta >= epsilon / (2 ||F||)).
  double forcing(double eta, double norm_old) const {
    constexpr double gamma = 0.9;
    const double ratio = norm_ / norm_old;
    double next = gamma * ratio * ratio;
    if (gamma * eta * eta > 0.1) next = std::max(next, gamma * eta * eta);
    next = std::min(next, settings_.linear_tolerance);
    return std::max(next, 0.5 * settings_.newton_tolerance / norm_);
  }

  SolveStats stats_;
  NonlinearProblem& problem_;
  CountedProblem counted_;
  Vector& x_;
  const NewtonSettings& settings_;
  Vector fx_, s_, rhs_, trial_, f_trial_, point_;
  double norm_ = 0;
  bool refresh_ = false;  // the last linear solve was slow: rebuild the preconditioner at the next iterate
};

}  // namespace

void validate(const NewtonSettings& s, const std::string& where) {
  require_positive(s.newton_tolerance, where, "newton_tolerance");
  if (!(s.linear_tolerance > 0 && s.linear_tolerance < 1))
    reject(where, "linear_tolerance", "a number in (0, 1)", s.linear_tolerance);
  require_positive(s.derivative_step, where, "derivative_step");
  require_at_least(s.restart, 1, where, "restart");
  require_at_least(s.max_newton, 1, where, "max_newton");
  require_at_least(s.max_krylov, 1, where, "max_krylov");
  require_at_least(s.max_backtracks, 0, where, "max_backtracks");
  require_at_least(s.refresh_after, 0, where, "refresh_after");
  if (s.krylov == Krylov::direct && !s.precondition)
    reject(where, "krylov",
           "precondition = true with a direct solve (it solves by the problem's factorisation)",
           "precondition = false");
}

SolveStats solve(NonlinearProblem& problem, Vector& x, const NewtonSettings& settings,
                 const Vector* residual_at_x) {
  validate(settings, "Newton-Krylov settings:");
  if (x.size() != problem.size())
    throw std::invalid_argument("newton_krylov solve: the initial guess has " + std::to_string(x.size()) +
                                " entries, the problem " + std::to_string(problem.size()));
  if (residual_at_x && residual_at_x->size() != x.size())
    throw std::invalid_argument("newton_krylov solve: the given residual has the wrong size");
  return Newton(problem, x, settings).run(residual_at_x);
}

bool directional_derivative(NonlinearProblem& problem, const Vector& x, const Vector& Fx, const Vector& s,
                            double h, Vector& out) {
  Vector point;
  return directional_derivative(problem, x, Fx, s, h, out, point);
}

bool directional_derivative(NonlinearProblem& problem, const Vector& x, const Vector& Fx, const Vector& s,
                            double h, Vector& out, Vector& point) {
  out.resize(x.size());
  const double s_norm = s.norm();
  if (s_norm == 0) {
    out.setZero();  // Sulsky & Kaul 2004, Eq. (2.4.18), s = 0
    return true;
  }
  // Sulsky & Kaul 2004, Eq. (2.4.18): step h ||x|| along s / ||s|| (h when x = 0), scaled back by ||s||
  const double x_norm = x.norm();
  const double step = x_norm > 0 ? h * x_norm : h;
  point = x + (step / s_norm) * s;
  if (!problem.residual(point, out)) return false;
  out = (out - Fx) * (s_norm / step);
  return true;
}

LinearStats conjugate_gradient(const LinearOperator& apply, const Vector& b, Vector& x, double tolerance,
                               int max_iterations, const LinearOperator& precondition) {
  if (x.size() != b.size()) x.setZero(b.size());
  const Eigen::Index n = b.size();
  Vector r(n), z(precondition ? n : 0), p(n), w(n);
  const Vector& zr = precondition ? z : r;  // z = P^{-1} r, or r itself without a preconditioner
  // Sulsky & Kaul 2004, Alg. 2-3, step 1
  initial_residual(apply, b, x, r);
  const double target = tolerance * b.norm();
  LinearStats stats{false, 0, r.norm()};
  if (precondition) precondition(r, z);
  double rho = r.dot(zr);
  // Alg. 3 normalises p_1 = r_0 / ||r_0||. With p_k = scale P_k, where P_k is the direction of Alg. 2 (unit
  // coefficient on z_{k-1}), r^T p_k = scale rho, so alpha and the next beta carry the factor `scale` (the
  // printed Alg. 3 omits it, which is exact only when ||r_0|| = 1).
  double scale = 1 / zr.norm();
  p = scale * zr;
  while (stats.residual_norm > target && stats.iterations < max_iterations) {
    // Alg. 2, step 2(a)-(g)
    apply(p, w);
    ++stats.iterations;
    const double pw = p.dot(w);
    if (!(pw > 0 && std::isfinite(pw))) break;  // not positive definite, or the operator failed
    const double alpha = scale * rho / pw;
    x += alpha * p;
    r -= alpha * w;
    stats.residual_norm = r.norm();
    if (precondition) precondition(r, z);
    const double rho_next = r.dot(zr);
    p = zr + (rho_next / rho / scale) * p;
    rho = rho_next;
    scale = 1;
  }
  stats.converged = stats.residual_norm <= target;
  return stats;
}

LinearStats gmres(const LinearOperator& apply, const Vector& b, Vector& x, double tolerance, int restart,
                  int max_iterations, const LinearOperator& precondition) {
  if (x.size() != b.size()) x.setZero(b.size());
  Gmres krylov(b.size(), std::max(1, std::min(restart, max_iterations)), apply, precondition);
  Vector& r = krylov.start_vector();
  initial_residual(apply, b, x, r);
  const double target = tolerance * b.norm();
  LinearStats stats{false, 0, r.norm()};
  while (stats.residual_norm > target && std::isfinite(stats.residual_norm) &&
         stats.iterations < max_iterations) {
    if (!krylov.cycle(stats.residual_norm, target, max_iterations, x, stats)) break;
    if (stats.residual_norm <= target || stats.iterations >= max_iterations) break;
    // restart from the true residual (Sulsky & Kaul 2004, end of Sec. 2.4.4)
    apply(x, r);
    r = b - r;
    stats.residual_norm = r.norm();
  }
  stats.converged = stats.residual_norm <= target;
  return stats;
}

}  // namespace mpm::numerics

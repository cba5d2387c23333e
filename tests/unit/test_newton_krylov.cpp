// The matrix-free Newton–Krylov solver (mpm/numerics/newton_krylov.hpp) on small analytic systems.
//
// Linear CG and GMRES are compared with dense Eigen factorisations; the forward difference of Sulsky & Kaul
// 2004, Eq. (2.4.18) with its closed form on a cubic system (where the Taylor series ends); Newton's method
// (Alg. 1) with its convergence order (Eq. 2.4.17 and 2.4.20); the line search (Sec. 3.2.3) on Kelley's
// arctan example; the counters in SolveStats with calls counted inside the test problems.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/numerics/newton_krylov.hpp"

namespace {

namespace nk = mpm::numerics;
using nk::Vector;
using Matrix = Eigen::MatrixXd;

// Entries uniform in [-1, 1] from a fixed seed (the tests are deterministic).
Matrix random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = u(gen);
  return m;
}

Vector random_vector(Eigen::Index n, unsigned seed) {
  return random_matrix(n, 1, seed);
}

double condition_number(const Matrix& a) {
  const Eigen::JacobiSVD<Matrix> svd(a);
  const Vector& sv = svd.singularValues();
  return sv(0) / sv(sv.size() - 1);
}

// A x for a dense matrix, counting products.
struct DenseOperator {
  const Matrix& a;
  int products = 0;
  nk::LinearOperator op() {
    return [this](const Vector& x, Vector& y) {
      ++products;
      y.noalias() = a * x;
    };
  }
};

// Jacobi preconditioner z = r ./ diag(A).
nk::LinearOperator jacobi(const Matrix& a) {
  return [d = Vector(a.diagonal())](const Vector& r, Vector& z) { z = r.cwiseQuotient(d); };
}

// F_i(x) = x_i^3 + (A x)_i - b_i with b chosen so that F(x_star) = 0; J(x) = diag(3 x^2) + A. With A SPD it
// is the gradient of the convex sum_i x_i^4 / 4 + x^T A x / 2 - b^T x, so J is SPD (the CG case).
class Cubic : public nk::NonlinearProblem {
 public:
  Cubic(Matrix a, const Vector& x_star)
      : a_(std::move(a)), b_(x_star.array().cube().matrix() + a_ * x_star) {}

  Eigen::Index size() const override { return b_.size(); }
  bool residual(const Vector& x, Vector& r) override {
    ++residual_calls;
    r = x.array().cube().matrix() + a_ * x - b_;
    return true;
  }
  bool jacobian_vector(const Vector& x, const Vector& s, Vector& js) override {
    if (!provide_jacobian) return false;
    ++jacobian_calls;
    js = jacobian(x) * s;
    return true;
  }
  bool precondition(const Vector& r, Vector& z) override {
    if (!provide_preconditioner) return false;
    z = r.cwiseQuotient(a_.diagonal());  // Jacobi on the linear part
    return true;
  }
  Matrix jacobian(const Vector& x) const {
    Matrix j = a_;
    j.diagonal() += 3 * x.array().square().matrix();
    return j;
  }

  int residual_calls = 0;
  int jacobian_calls = 0;
  bool provide_jacobian = false;
  bool provide_preconditioner = false;

 private:
  Matrix a_;
  Vector b_;
};

// n x n SPD matrix with eigenvalues >= 1: M^T M / n + I.
Matrix spd_matrix(Eigen::Index n, unsigned seed) {
  const Matrix m = random_matrix(n, n, seed);
  return m.transpose() * m / static_cast<double>(n) + Matrix::Identity(n, n);
}

// n x n non-symmetric matrix 2 I + M / sqrt(n) (eigenvalues in a disc of radius ~0.6 about 2).
Matrix nonsymmetric_matrix(Eigen::Index n, unsigned seed) {
  return 2 * Matrix::Identity(n, n) + random_matrix(n, n, seed) / std::sqrt(static_cast<double>(n));
}

// A componentwise system F_i(x) = f(x_i), counting residual calls; f returns NaN where F is undefined, and
// the residual then fails (like an MPM residual at a velocity that would invert a material point).
class Componentwise : public nk::NonlinearProblem {
 public:
  Componentwise(Eigen::Index n, std::function<double(double)> f) : n_(n), f_(std::move(f)) {}
  Eigen::Index size() const override { return n_; }
  bool residual(const Vector& x, Vector& r) override {
    ++residual_calls;
    r = x.unaryExpr(f_);
    return !r.hasNaN();
  }
  int residual_calls = 0;

 private:
  Eigen::Index n_;
  std::function<double(double)> f_;
};

// F_i(x) = atan(x_i): full Newton steps from x = 10 overshoot to -139 and diverge (Kelley 1995, Ch. 8).
Componentwise arctan(Eigen::Index n) {
  return Componentwise(n, [](double x) { return std::atan(x); });
}

// F_i(x) = ln(x_i / a), defined for x > 0 only.
Componentwise logarithm(Eigen::Index n, double a) {
  return Componentwise(n, [a](double x) { return x > 0 ? std::log(x / a) : std::nan(""); });
}

// ||F_{n+1}|| / ||F_n||^p over the recorded norms, for the steps whose result is above `floor`.
std::vector<double> order_ratios(const std::vector<double>& norms, double p, double floor) {
  std::vector<double> ratios;
  for (std::size_t i = 0; i + 1 < norms.size(); ++i)
    if (norms[i + 1] > floor) ratios.push_back(norms[i + 1] / std::pow(norms[i], p));
  return ratios;
}

std::string join(const std::vector<double>& v) {
  std::string s;
  char buf[32];
  for (double x : v) {
    std::snprintf(buf, sizeof buf, "%.3e ", x);
    s += buf;
  }
  return s;
}

// ---- linear solvers -------------------------------------------------------------------------------------

TEST(LinearKrylov, CgMatchesCholeskyOnRandomSpd) {
  const Eigen::Index n = 40;
  const Matrix m = random_matrix(n, n, 1);
  const Matrix a = m.transpose() * m / 4 + Matrix::Identity(n, n);
  const Vector b = random_vector(n, 2);
  const Vector exact = a.llt().solve(b);
  // ||x - x*|| / ||x*|| <= cond(A) ||r|| / ||b|| <= cond(A) 1e-12: with cond < 100 that is < 1e-10.
  const double cond = condition_number(a);
  ASSERT_LT(cond, 100.0);
  DenseOperator op{a};
  Vector x;
  const nk::LinearStats st = nk::conjugate_gradient(op.op(), b, x, 1e-12, 1000);
  EXPECT_TRUE(st.converged);
  EXPECT_LE(st.residual_norm, 1e-12 * b.norm());
  EXPECT_LT((x - exact).norm() / exact.norm(), 1e-10);
  // At most n steps (Sulsky & Kaul 2004, Sec. 2.4.3; exact in exact arithmetic, here also by the rate
  // 2 ((sqrt(13) - 1) / (sqrt(13) + 1))^k <= 1e-12 at k ~ 47 bound); measured 37 with cond(A) = 13.1.
  EXPECT_LE(st.iterations, n);
  EXPECT_EQ(op.products, st.iterations);  // x_0 = 0: no product for r_0
  // The recursive residual is the true one to round-off (1e-12 ||b|| plus ~cond * eps ||b||).
  EXPECT_LT((b - a * x).norm(), 2e-12 * b.norm());
}

TEST(LinearKrylov, CgTerminatesAfterAsManyStepsAsDistinctEigenvalues) {
  // A = Q diag(1, 2, 5, 10, each 10 times) Q^T: the minimal polynomial has degree 4, so CG (and full GMRES)
  // reach the solution in 4 steps up to round-off (Kelley 1995, Sec. 2.2).
  const Eigen::Index n = 40;
  const Eigen::HouseholderQR<Matrix> qr(random_matrix(n, n, 26));
  const Matrix q = qr.householderQ();
  Vector lambda(n);
  for (Eigen::Index i = 0; i < n; ++i) lambda(i) = std::array<double, 4>{1, 2, 5, 10}[i % 4];
  const Matrix a = q * lambda.asDiagonal() * q.transpose();
  const Vector b = random_vector(n, 27);
  const Vector exact = a.llt().solve(b);
  Vector x_cg, x_gmres;
  DenseOperator op{a};
  const nk::LinearStats cg = nk::conjugate_gradient(op.op(), b, x_cg, 1e-12, 100);
  const nk::LinearStats gm = nk::gmres(op.op(), b, x_gmres, 1e-12, 50, 100);
  EXPECT_TRUE(cg.converged);
  EXPECT_TRUE(gm.converged);
  EXPECT_EQ(cg.iterations, 4);  // measured relative residual after 4 steps: 6e-15 (CG), 7e-15 (GMRES)
  EXPECT_EQ(gm.iterations, 4);
  EXPECT_LT((x_cg - exact).norm() / exact.norm(), 1e-10);  // cond(A) = 10
  EXPECT_LT((x_gmres - exact).norm() / exact.norm(), 1e-10);
}

TEST(LinearKrylov, CgFromNonzeroGuessAndZeroRightHandSide) {
  const Eigen::Index n = 20;
  const Matrix a = spd_matrix(n, 3);
  const Vector b = random_vector(n, 4);
  const Vector exact = a.llt().solve(b);
  DenseOperator op{a};
  Vector x = exact + 1e-3 * random_vector(n, 5);
  const nk::LinearStats st = nk::conjugate_gradient(op.op(), b, x, 1e-12, 100);
  EXPECT_TRUE(st.converged);
  EXPECT_LT((x - exact).norm() / exact.norm(), 1e-10);  // cond(A) < 10 here, same argument as above
  EXPECT_EQ(op.products, st.iterations + 1);            // one product for r_0 = b - A x_0
  Vector zero = Vector::Zero(n);
  const nk::LinearStats none = nk::conjugate_gradient(op.op(), Vector::Zero(n), zero, 1e-12, 100);
  EXPECT_TRUE(none.converged);
  EXPECT_EQ(none.iterations, 0);
  EXPECT_EQ(zero.norm(), 0.0);
}

TEST(LinearKrylov, GmresMatchesLuOnRandomNonsymmetric) {
  const Eigen::Index n = 40;
  const Matrix a = nonsymmetric_matrix(n, 6);
  ASSERT_GT((a - a.transpose()).norm(), 1.0);
  const Vector b = random_vector(n, 7);
  const Vector exact = a.partialPivLu().solve(b);
  const double cond = condition_number(a);
  ASSERT_LT(cond, 100.0);  // so that a relative residual of 1e-12 gives a relative error below 1e-10
  for (int restart : {10, 50}) {
    DenseOperator op{a};
    Vector x;
    const nk::LinearStats st = nk::gmres(op.op(), b, x, 1e-12, restart, 1000);
    EXPECT_TRUE(st.converged) << "restart " << restart;
    EXPECT_LT((x - exact).norm() / exact.norm(), 1e-10) << "restart " << restart;
    EXPECT_LT((b - a * x).norm(), 2e-12 * b.norm()) << "the Arnoldi estimate is the true residual";
    const int restarts = (st.iterations - 1) / restart;
    EXPECT_EQ(op.products, st.iterations + restarts);  // one product for each restart's true residual
    // Measured (cond(A) = 2.2): 21 iterations with two restarts for m = 10, 20 without restart for m = 50.
    if (restart == 10) {
      EXPECT_GT(st.iterations, restart) << "the test must exercise restarts";
    } else {
      EXPECT_LE(st.iterations, n) << "full GMRES terminates in at most n steps";
    }
  }
}

TEST(LinearKrylov, JacobiPreconditioningHelpsOnBadlyScaledSystems) {
  const Eigen::Index n = 40;
  // Diagonal scales from 1 to 1e6; A = D^(1/2) (I + E) D^(1/2) with E symmetric, ||E||_2 = 0.5 (SPD), and
  // A = D (I + E') with E' non-symmetric, ||E'||_2 = 0.5.
  Vector d(n);
  for (Eigen::Index i = 0; i < n; ++i) d(i) = std::pow(10.0, 6.0 * static_cast<double>(i) / (n - 1.0));
  const Matrix s = random_matrix(n, n, 8);
  Matrix e = s + s.transpose();
  e *= 0.5 / e.operatorNorm();
  const Matrix sqrt_d = d.cwiseSqrt().asDiagonal();
  const Matrix spd = sqrt_d * (Matrix::Identity(n, n) + e) * sqrt_d;
  Matrix e2 = random_matrix(n, n, 9);
  e2 *= 0.5 / e2.operatorNorm();
  const Matrix general = d.asDiagonal() * (Matrix::Identity(n, n) + e2);
  const Vector b = random_vector(n, 10);

  DenseOperator cg_op{spd};
  Vector x_plain, x_pre;
  const nk::LinearStats cg_plain = nk::conjugate_gradient(cg_op.op(), b, x_plain, 1e-10, 1000);
  const nk::LinearStats cg_pre = nk::conjugate_gradient(cg_op.op(), b, x_pre, 1e-10, 1000, jacobi(spd));
  EXPECT_TRUE(cg_pre.converged);
  EXPECT_LT((spd * x_pre - b).norm(), 1e-9 * b.norm());
  // Measured: 19 preconditioned CG iterations (cond(P^{-1} A) <= 3), 183 without (cond(A) ~ 1e6).
  EXPECT_TRUE(cg_plain.converged);
  EXPECT_LE(cg_pre.iterations, 25);
  EXPECT_GT(cg_plain.iterations, 5 * cg_pre.iterations);

  DenseOperator gm_op{general};
  const nk::LinearStats gm_plain = nk::gmres(gm_op.op(), b, x_plain, 1e-10, 20, 1000);
  const nk::LinearStats gm_pre = nk::gmres(gm_op.op(), b, x_pre, 1e-10, 20, 1000, jacobi(general));
  EXPECT_TRUE(gm_pre.converged);
  EXPECT_LT((general * x_pre - b).norm(), 1e-9 * b.norm());  // right preconditioning: true residual
  // Measured: 18 preconditioned GMRES(20) iterations; without, it stagnates and stops unconverged at 1000.
  EXPECT_LE(gm_pre.iterations, 25);
  EXPECT_FALSE(gm_plain.converged);
  EXPECT_EQ(gm_plain.iterations, 1000);
}

TEST(LinearKrylov, StopsWhenTheOperatorFails) {
  const Eigen::Index n = 10;
  const Matrix a = spd_matrix(n, 11);
  const Vector b = random_vector(n, 12);
  int calls = 0;
  // Fails (non-finite output) on the third product.
  const nk::LinearOperator failing = [&](const Vector& x, Vector& y) {
    y = ++calls == 3 ? Vector::Constant(n, std::numeric_limits<double>::quiet_NaN()) : Vector(a * x);
  };
  for (bool use_cg : {true, false}) {
    calls = 0;
    Vector x;
    const nk::LinearStats st =
        use_cg ? nk::conjugate_gradient(failing, b, x, 1e-12, 100) : nk::gmres(failing, b, x, 1e-12, 20, 100);
    EXPECT_FALSE(st.converged);
    EXPECT_EQ(st.iterations, 3);
    EXPECT_TRUE(x.allFinite());
    // Two good directions reduce the residual (minimisation over a 2-D Krylov space).
    EXPECT_LT((b - a * x).norm(), b.norm());
    EXPECT_NEAR(st.residual_norm, (b - a * x).norm(), 1e-12 * b.norm());
  }
}

// ---- Eq. (2.4.18) ---------------------------------------------------------------------------------------

TEST(DirectionalDerivative, MatchesClosedFormOfCubicDifference) {
  // For the cubic, F(x + t u) - F(x) = t J u + t^2 3 x u^2 + t^3 u^3 exactly (componentwise powers), so with
  // u = s / ||s|| and t = h ||x||: D_h F = J s + ||s|| (3 t x u^2 + t^2 u^3).
  const Eigen::Index n = 8;
  Cubic f(nonsymmetric_matrix(n, 13), random_vector(n, 14));
  const Vector x = random_vector(n, 15), s = 3 * random_vector(n, 16);
  Vector fx, d;
  f.residual(x, fx);
  const Vector js = f.jacobian(x) * s;
  const Vector u = s / s.norm();
  const double scale =
      3 * x.norm() * x.lpNorm<Eigen::Infinity>() * s.norm();  // bound of ||F''[u,u]|| t/2 / h
  std::vector<double> errors;
  for (double h : {1e-3, 1e-4, 1e-5, 1e-7}) {
    const int calls = f.residual_calls;
    ASSERT_TRUE(nk::directional_derivative(f, x, fx, s, h, d));
    EXPECT_EQ(f.residual_calls, calls + 1);  // one evaluation per product
    const double t = h * x.norm();
    const Vector closed =
        js + s.norm() * (3 * t * x.array() * u.array().square() + t * t * u.array().cube()).matrix();
    // Round-off: F is evaluated to ~1e-15 (entries of size ~10), divided by t >= 1e-7.
    EXPECT_LT((d - closed).norm(), 1e-15 * 10 / t * s.norm()) << "h = " << h;
    errors.push_back((d - js).norm());
    EXPECT_LT(errors.back(), 10 * h * scale) << "h = " << h;  // first-order truncation, Eq. (2.4.18)
  }
  // First order: 100 times smaller h, 100 times smaller error (the O(h^2) term is 1e-3 of it at h = 1e-3).
  // Measured errors 6.750e-3, 6.749e-4, 6.749e-5, 6.744e-7 (ratio 100.003 between h = 1e-3 and 1e-5).
  EXPECT_NEAR(errors[0] / errors[2], 100.0, 1.0);
}

TEST(DirectionalDerivative, ZeroPointAndZeroDirection) {
  const Eigen::Index n = 6;
  const Matrix a = nonsymmetric_matrix(n, 17);
  Cubic f(a, random_vector(n, 18));
  const Vector zero = Vector::Zero(n), s = random_vector(n, 19);
  Vector f0, d;
  f.residual(zero, f0);
  // x = 0: the step is h itself, and D_h F = A s + h^2 ||s|| u^3 exactly (J(0) = A).
  const double h = 1e-3;
  ASSERT_TRUE(nk::directional_derivative(f, zero, f0, s, h, d));
  const Vector u = s / s.norm();
  const Vector closed = a * s + (h * h * s.norm()) * u.array().cube().matrix();
  EXPECT_LT((d - closed).norm(), 1e-15 * 10 / h * s.norm());  // round-off as above, t = h
  EXPECT_GT((d - a * s).norm(), 0.1 * h * h * s.norm() * u.array().cube().matrix().norm());
  // s = 0: zero, without evaluating F.
  const int calls = f.residual_calls;
  d.setConstant(7.0);
  ASSERT_TRUE(nk::directional_derivative(f, random_vector(n, 20), f0, zero, h, d));
  EXPECT_EQ(d.norm(), 0.0);
  EXPECT_EQ(f.residual_calls, calls);
}

TEST(DirectionalDerivative, ReportsAFailedResidual) {
  Componentwise f = logarithm(2, 1.0);
  const Vector x = Vector::Constant(2, 1e-8), s = (Vector(2) << -1.0, 0.0).finished();
  Vector fx, d;
  ASSERT_TRUE(f.residual(x, fx));
  // The perturbed point x + h ||x|| s/||s|| stays positive for h = 0.5 and crosses zero for h = 2.
  EXPECT_TRUE(nk::directional_derivative(f, x, fx, s, 0.5, d));
  EXPECT_FALSE(nk::directional_derivative(f, x, fx, s, 2.0, d));
}

// ---- Newton ---------------------------------------------------------------------------------------------

nk::NewtonSettings tight(nk::Krylov krylov) {
  nk::NewtonSettings s;
  s.krylov = krylov;
  s.newton_tolerance = 1e-12;
  s.linear_tolerance = 1e-12;
  s.derivative_step = 1e-7;
  return s;
}

const char* name(nk::Krylov k) {
  return k == nk::Krylov::cg ? "CG" : "GMRES";
}

// The cubic system for a Krylov method: SPD A for CG (J SPD), non-symmetric A for GMRES.
Cubic cubic_for(nk::Krylov krylov, const Vector& x_star) {
  const Eigen::Index n = x_star.size();
  return Cubic(krylov == nk::Krylov::cg ? spd_matrix(n, 22) : nonsymmetric_matrix(n, 22), x_star);
}

// Newton on the cubic system from x_0 = 0 (n = 10, x_star uniform in [-1, 1]); epsilon = 1e-12 is ~100 times
// the round-off floor of ||F|| (entries of size ~1-10 summed over 10 components: ~1e-14).
constexpr Eigen::Index newton_n = 10;
constexpr double norm_floor = 1e-14;

struct CubicRun {
  nk::SolveStats stats;
  Cubic problem;
  Vector x;
};

CubicRun run_cubic(const nk::NewtonSettings& s, bool exact = false, bool precondition = false) {
  const Vector x_star = random_vector(newton_n, 21);
  CubicRun r{{}, cubic_for(s.krylov, x_star), Vector::Zero(newton_n)};
  r.problem.provide_jacobian = exact;
  r.problem.provide_preconditioner = precondition;
  r.stats = nk::solve(r.problem, r.x, s);
  return r;
}

constexpr nk::Krylov both[] = {nk::Krylov::cg, nk::Krylov::gmres};

TEST(Newton, QuadraticWithTightLinearTolerance) {
  // Sulsky & Kaul 2004, Eq. (2.4.17) and Sec. 3.2.2: with gamma = 1e-12 the inexact Newton method is
  // quadratic. h = 1e-7 keeps the first-order error of Eq. (2.4.18) (relative ~3 h ||x|| ||x||_inf, see
  // above) below the quadratic term down to ||F|| ~ 1e-8. Measured ||F_{n+1}|| / ||F_n||^2 <= 0.174 (CG) and
  // 0.152 (GMRES) over all steps; asserting < 0.5. Measured 6 Newton iterations for both.
  for (nk::Krylov krylov : both) {
    const CubicRun r = run_cubic(tight(krylov));
    const nk::SolveStats& st = r.stats;
    ASSERT_TRUE(st.converged) << name(krylov) << ": " << st.failure;
    EXPECT_TRUE(st.failure.empty());
    EXPECT_LE(st.residual_norms.back(), 1e-12);
    // ||x - x*|| <~ ||J^{-1}|| ||F||, with ||J^{-1}|| <= 1 (CG: J >= I) or ~1.2 (GMRES: sigma_min(J) ~ 0.85).
    EXPECT_LT((r.x - random_vector(newton_n, 21)).norm(), 1e-11);
    EXPECT_LE(st.newton_iterations, 8) << name(krylov);
    EXPECT_EQ(st.residual_norms.size(), static_cast<std::size_t>(st.newton_iterations) + 1);
    const std::vector<double> ratios = order_ratios(st.residual_norms, 2.0, norm_floor);
    ASSERT_GE(ratios.size(), 4u);
    for (double q : ratios) EXPECT_LT(q, 0.5) << name(krylov) << " norms " << join(st.residual_norms);
    // The last step is quadratic down to the round-off floor: ||F_N|| < max(||F_{N-1}||^2, 1e-14) (measured
    // 4.49e-8 -> 6.7e-15 for CG and 2.42e-9 -> 1.44e-15 for GMRES).
    const auto& f = st.residual_norms;
    EXPECT_LT(f[f.size() - 1], std::max(f[f.size() - 2] * f[f.size() - 2], norm_floor));
  }
}

TEST(Newton, LinearWithLooseLinearTolerance) {
  // With gamma = 0.1, ||F_{n+1}|| <= gamma ||F_n|| + O(||F_n||^2) (Sulsky & Kaul 2004, Eq. 2.4.20; Kelley
  // 1995, Sec. 6.1). Measured for n >= 3: ratios <= 0.099 (CG) and 0.080 (GMRES); asserting <= 0.15.
  // Measured 11 (CG) and 12 (GMRES) Newton iterations against 6 with gamma = 1e-12, and 25 / 24 Krylov
  // iterations against 68 / 60.
  for (nk::Krylov krylov : both) {
    nk::NewtonSettings s = tight(krylov);
    s.linear_tolerance = 0.1;
    const CubicRun loose = run_cubic(s);
    const CubicRun sharp = run_cubic(tight(krylov));
    ASSERT_TRUE(loose.stats.converged) << loose.stats.failure;
    const std::vector<double> linear = order_ratios(loose.stats.residual_norms, 1.0, norm_floor);
    for (std::size_t i = 3; i < linear.size(); ++i)
      EXPECT_LE(linear[i], 0.15) << name(krylov) << " step " << i;
    // Not quadratic: ||F_{n+1}|| / ||F_n||^2 grows without bound (measured > 7e9 at the end; < 0.5 above).
    EXPECT_GT(order_ratios(loose.stats.residual_norms, 2.0, norm_floor).back(), 1e6) << name(krylov);
    EXPECT_GE(loose.stats.newton_iterations, sharp.stats.newton_iterations + 4) << name(krylov);
    EXPECT_LT(2 * loose.stats.krylov_iterations, sharp.stats.krylov_iterations) << name(krylov);
  }
}

TEST(Newton, EisenstatWalkerSavesKrylovIterations) {
  // Eisenstat & Walker 1996 choice 2 capped at eta_max = 0.1: measured 23 (CG) and 24 (GMRES) Krylov
  // iterations in 6 Newton iterations, against 68 / 60 with constant gamma = 1e-12 (6 Newton iterations) and
  // 11 / 12 Newton iterations with constant gamma = 0.1.
  for (nk::Krylov krylov : both) {
    nk::NewtonSettings s = tight(krylov);
    s.forcing = nk::Forcing::eisenstat_walker;
    s.linear_tolerance = 0.1;
    const CubicRun adaptive = run_cubic(s);
    s.forcing = nk::Forcing::constant;
    const CubicRun loose = run_cubic(s);
    const CubicRun sharp = run_cubic(tight(krylov));
    ASSERT_TRUE(adaptive.stats.converged) << adaptive.stats.failure;
    EXPECT_LT(2 * adaptive.stats.krylov_iterations, sharp.stats.krylov_iterations) << name(krylov);
    EXPECT_LT(adaptive.stats.newton_iterations, loose.stats.newton_iterations) << name(krylov);
    EXPECT_LE(adaptive.stats.newton_iterations, sharp.stats.newton_iterations + 1) << name(krylov);
  }
}

TEST(Newton, ExactJacobianProductsReplaceDifferences) {
  // Same iterates as with Eq. (2.4.18) at h = 1e-7 (measured 6 iterations each, 60 products for both
  // methods), but each Krylov iteration costs a Jacobian product instead of a residual evaluation.
  for (nk::Krylov krylov : both) {
    nk::NewtonSettings s = tight(krylov);
    const CubicRun differenced = run_cubic(s);
    s.exact_jacobian = true;
    const CubicRun exact = run_cubic(s, true);
    ASSERT_TRUE(exact.stats.converged) << exact.stats.failure;
    EXPECT_EQ(exact.stats.jacobian_products, exact.problem.jacobian_calls);
    EXPECT_EQ(exact.stats.jacobian_products, exact.stats.krylov_iterations);
    EXPECT_GT(exact.stats.jacobian_products, 0);
    EXPECT_EQ(exact.stats.residual_evaluations, 1 + exact.stats.newton_iterations + exact.stats.backtracks);
    EXPECT_LE(exact.stats.newton_iterations, differenced.stats.newton_iterations) << name(krylov);
    EXPECT_EQ(differenced.stats.jacobian_products, 0);
    EXPECT_EQ(differenced.problem.jacobian_calls, 0);
  }
}

TEST(Newton, CountsEveryResidualEvaluation) {
  // Without GMRES restarts (<= n = 10 Krylov iterations per step < m = 20) each Krylov iteration is one
  // D_h F, i.e. one residual, and each Newton step one accepted plus `backtracks` rejected trial points:
  // evaluations = 1 + krylov + newton + backtracks.
  for (nk::Krylov krylov : both) {
    for (double gamma : {1e-12, 0.1}) {
      nk::NewtonSettings s = tight(krylov);
      s.linear_tolerance = gamma;
      const CubicRun r = run_cubic(s);
      const nk::SolveStats& st = r.stats;
      ASSERT_TRUE(st.converged);
      EXPECT_EQ(st.residual_evaluations, r.problem.residual_calls);
      EXPECT_EQ(st.residual_evaluations, 1 + st.krylov_iterations + st.newton_iterations + st.backtracks);
    }
  }
  Componentwise f = arctan(3);
  Vector x = Vector::Constant(3, 10.0);
  const nk::SolveStats st = nk::solve(f, x, tight(nk::Krylov::gmres));
  ASSERT_TRUE(st.converged);
  ASSERT_GT(st.backtracks, 0);
  EXPECT_EQ(st.residual_evaluations, f.residual_calls);
  EXPECT_EQ(st.residual_evaluations, 1 + st.krylov_iterations + st.newton_iterations + st.backtracks);
}

TEST(Newton, LineSearchRescuesArctan) {
  // Kelley 1995, Ch. 8: from x_0 = 10 the full Newton step goes to 10 - 101 atan(10) = -138.6 and the
  // iterates run away; the Armijo line search converges. Measured: 12 Newton iterations and 10 halvings for
  // both n = 1 and n = 3 (the components are identical); without it the residual saturates at pi/2 per
  // component, D_h F vanishes and the solve stops after 4 iterations.
  for (Eigen::Index n : {1, 3}) {
    Componentwise f = arctan(n);
    nk::NewtonSettings s = tight(nk::Krylov::gmres);
    Vector x = Vector::Constant(n, 10.0);
    const nk::SolveStats with = nk::solve(f, x, s);
    ASSERT_TRUE(with.converged) << with.failure;
    EXPECT_GT(with.backtracks, 0);
    EXPECT_LE(with.newton_iterations, 15);
    EXPECT_LT(x.norm(), 1e-12);  // atan(x) ~ x near the root
    for (std::size_t i = 0; i + 1 < with.residual_norms.size(); ++i)
      EXPECT_LT(with.residual_norms[i + 1], with.residual_norms[i]);  // sufficient decrease at every step
    s.line_search = false;
    x = Vector::Constant(n, 10.0);
    const nk::SolveStats without = nk::solve(f, x, s);
    EXPECT_FALSE(without.converged);
    EXPECT_FALSE(without.failure.empty());
    EXPECT_EQ(without.backtracks, 0);
    EXPECT_GT(without.residual_norms.back(), without.residual_norms.front());  // the full steps made it worse
  }
}

TEST(Newton, LineSearchBacksOffWhereTheResidualFails) {
  // F = ln(x / a) from x_0 = 10 a: the full step -x ln(x / a) lands at 10 a (1 - ln 10) < 0 where F fails,
  // and so does the half step; the quarter step reaches 10 a (1 - ln(10) / 4) = 4.24 a, where
  // ln 4.24 = 1.44 < ln 10 = 2.30 is a sufficient decrease.
  Componentwise f = logarithm(2, 2.0);
  nk::NewtonSettings s = tight(nk::Krylov::gmres);
  Vector x = Vector::Constant(2, 20.0);
  const nk::SolveStats with = nk::solve(f, x, s);
  ASSERT_TRUE(with.converged) << with.failure;
  EXPECT_GE(with.backtracks, 2);
  EXPECT_LT((x - Vector::Constant(2, 2.0)).norm(), 1e-11);  // |x - a| ~ a |F| = 2e-12
  s.line_search = false;
  x = Vector::Constant(2, 20.0);
  const nk::SolveStats without = nk::solve(f, x, s);
  EXPECT_FALSE(without.converged);
  EXPECT_EQ(without.failure, "F cannot be evaluated at the Newton step");
  EXPECT_EQ(x, Vector::Constant(2, 20.0));  // the failed point is not returned
}

TEST(Newton, ReportsFailuresWithoutThrowing) {
  nk::NewtonSettings s = tight(nk::Krylov::gmres);
  // Too few Newton iterations: 2 steps from ||F|| = 5.35 leave 0.532 (measured above).
  s.max_newton = 2;
  const CubicRun capped = run_cubic(s);
  EXPECT_FALSE(capped.stats.converged);
  EXPECT_EQ(capped.stats.newton_iterations, 2);
  EXPECT_EQ(capped.stats.failure.rfind("no convergence in 2 Newton iterations (||F|| = 5.32", 0), 0u)
      << capped.stats.failure;
  // No backtracking allowed: the first arctan step fails the Armijo test.
  s = tight(nk::Krylov::gmres);
  s.max_backtracks = 0;
  Componentwise f = arctan(1);
  Vector x = Vector::Constant(1, 10.0);
  const nk::SolveStats line = nk::solve(f, x, s);
  EXPECT_FALSE(line.converged);
  EXPECT_EQ(line.failure.rfind("line search failed", 0), 0u) << line.failure;
  EXPECT_EQ(x(0), 10.0);
  // A non-finite residual.
  Componentwise inf(2, [](double v) { return v * std::numeric_limits<double>::infinity(); });
  x = Vector::Ones(2);
  EXPECT_EQ(nk::solve(inf, x, s).failure, "non-finite residual norm");
  // F undefined at the initial guess.
  Componentwise log2 = logarithm(2, 1.0);
  x = -Vector::Ones(2);
  EXPECT_EQ(nk::solve(log2, x, s).failure, "F cannot be evaluated at the initial guess");
  // D_h F infeasible: with h = 1.2, F = ln(x) and x_0 = (1.5, 1.5) the difference point moves by
  // 1.2 ||x_0|| = 2.55 along -F / ||F|| = -(1, 1) / sqrt(2), i.e. by -1.8 per component, below zero. The
  // Krylov solve stops at its first product with s = 0.
  s.derivative_step = 1.2;
  Componentwise g = logarithm(2, 1.0);
  x = Vector::Constant(2, 1.5);
  const nk::SolveStats d = nk::solve(g, x, s);
  EXPECT_FALSE(d.converged);
  EXPECT_EQ(d.derivative_failures, 1);
  EXPECT_EQ(d.krylov_iterations, 1);
  EXPECT_EQ(d.residual_evaluations, 2);
  EXPECT_EQ(d.failure.rfind("the Krylov solve produced no step", 0), 0u) << d.failure;
}

TEST(Newton, JacobiPreconditionerReducesKrylovIterations) {
  // The cubic with A = D^(1/2) (I + E) D^(1/2) (GMRES: D (I + E')), D from 1 to 1e4, and P = diag(A).
  const Eigen::Index n = 20;
  Vector d(n);
  for (Eigen::Index i = 0; i < n; ++i) d(i) = std::pow(10.0, 4.0 * static_cast<double>(i) / (n - 1.0));
  Matrix e = random_matrix(n, n, 23);
  for (nk::Krylov krylov : both) {
    Matrix a;
    if (krylov == nk::Krylov::cg) {
      Matrix sym = e + e.transpose();
      sym *= 0.5 / sym.operatorNorm();
      a = d.cwiseSqrt().asDiagonal() * (Matrix::Identity(n, n) + sym) * d.cwiseSqrt().asDiagonal();
    } else {
      a = d.asDiagonal() * (Matrix::Identity(n, n) + 0.5 / e.operatorNorm() * e);
    }
    nk::NewtonSettings s = tight(krylov);
    s.newton_tolerance = 1e-8;  // ||F|| floor ~ eps * 1e4 * ||x||
    s.linear_tolerance = 1e-6;
    s.restart = 10;  // GMRES(10) on the 20 unknowns: unpreconditioned restarts stagnate
    int iterations[2] = {0, 0};
    for (bool pre : {false, true}) {
      Cubic f(a, random_vector(n, 24));
      f.provide_preconditioner = pre;
      s.precondition = pre;
      Vector x = Vector::Zero(n);
      const nk::SolveStats st = nk::solve(f, x, s);
      ASSERT_TRUE(st.converged) << name(krylov) << (pre ? " preconditioned: " : ": ") << st.failure;
      iterations[pre] = st.krylov_iterations;
    }
    // Measured Krylov iterations (5 Newton steps each): CG 58 vs 230, GMRES(10) 64 vs 1441.
    EXPECT_LT(3 * iterations[1], iterations[0]) << name(krylov);
  }
}

// A lagged Jacobian preconditioner: the exact J(x) factorised at the last refresh point, starting from J(x_0)
// at x_0 = 0, where the cubic term vanishes (J = A). Far from x_0 the frozen J goes stale.
class LaggedCubic : public Cubic {
 public:
  using Cubic::Cubic;
  bool precondition(const Vector& r, Vector& z) override {
    z = lu_.solve(r);
    return true;
  }
  bool refresh_preconditioner(const Vector& x, const Vector& /*fx*/) override {
    ++refreshes;
    lu_.compute(jacobian(x));
    return true;
  }
  int refreshes = 0;

 private:
  Eigen::PartialPivLU<Matrix> lu_{jacobian(Vector::Zero(size()))};
};

TEST(Newton, StalePreconditionerIsRefreshedAfterASlowSolve) {
  // x_star with entries up to 3: the cubic term (3 x^2 up to 27 on the diagonal) dominates J(x_star), so J(0)
  // = A is a poor preconditioner near the root. Measured (GMRES, 20 unknowns, gamma = 1e-6): 6 Newton steps
  // either way, 92 Krylov iterations without refreshes and 27 with refresh_after = 2 (2 refreshes).
  const Eigen::Index n = 20;
  const Vector x_star = 3 * random_vector(n, 26);
  nk::NewtonSettings s = tight(nk::Krylov::gmres);
  s.newton_tolerance = 1e-9;
  s.linear_tolerance = 1e-6;
  s.precondition = true;
  int krylov[2] = {0, 0};
  for (int refresh_after : {0, 2}) {
    LaggedCubic f(spd_matrix(n, 27), x_star);
    s.refresh_after = refresh_after;
    Vector x = Vector::Zero(n);
    const nk::SolveStats st = nk::solve(f, x, s);
    ASSERT_TRUE(st.converged) << st.failure;
    EXPECT_LT((x - x_star).norm(), 1e-8);
    EXPECT_EQ(st.refreshes, f.refreshes);
    if (refresh_after == 0) {
      EXPECT_EQ(st.refreshes, 0);
    } else {
      EXPECT_GE(st.refreshes, 1);
    }
    std::printf("refresh_after %d: %d Newton, %d Krylov, %d refreshes\n", refresh_after, st.newton_iterations,
                st.krylov_iterations, st.refreshes);
    krylov[refresh_after > 0] = st.krylov_iterations;
  }
  EXPECT_LT(2 * krylov[1], krylov[0]);
}

TEST(Newton, GivenInitialResidualSavesOneEvaluation) {
  // F(x_0) handed in is the same F the solver would compute: the same iterates bit for bit, one call fewer.
  const nk::NewtonSettings s = tight(nk::Krylov::gmres);
  const Vector x_star = random_vector(newton_n, 21);
  Cubic plain = cubic_for(nk::Krylov::gmres, x_star), given = cubic_for(nk::Krylov::gmres, x_star);
  Vector x_plain = Vector::Zero(newton_n), x_given = Vector::Zero(newton_n), f0;
  given.residual(x_given, f0);
  const int calls_before = given.residual_calls;
  const nk::SolveStats a = nk::solve(plain, x_plain, s), b = nk::solve(given, x_given, s, &f0);
  EXPECT_EQ(b.residual_evaluations, a.residual_evaluations - 1);
  EXPECT_EQ(given.residual_calls - calls_before, plain.residual_calls - 1);
  EXPECT_EQ(x_plain, x_given);
  Vector wrong = Vector::Zero(newton_n + 1);
  EXPECT_THROW(nk::solve(given, x_given, s, &wrong), std::invalid_argument);
}

TEST(Newton, MissingOptionalOperatorsAreInputErrors) {
  nk::NewtonSettings s = tight(nk::Krylov::gmres);
  s.exact_jacobian = true;
  EXPECT_THROW(run_cubic(s, false), mpm::InputError);
  s.exact_jacobian = false;
  s.precondition = true;
  EXPECT_THROW(run_cubic(s, false, false), mpm::InputError);
  Cubic f = cubic_for(nk::Krylov::gmres, random_vector(3, 25));
  Vector wrong = Vector::Zero(4);
  EXPECT_THROW(nk::solve(f, wrong, tight(nk::Krylov::gmres)), std::invalid_argument);
}

// ---- settings -------------------------------------------------------------------------------------------

std::string validation_error(const nk::NewtonSettings& s) {
  try {
    nk::validate(s, "scene.toml: [implicit]");
  } catch (const mpm::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(NewtonSettings, ValidateNamesTheBadKey) {
  EXPECT_EQ(validation_error(nk::NewtonSettings{}), "");
  struct Case {
    const char* key;
    std::function<void(nk::NewtonSettings&)> spoil;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases = {
      {"newton_tolerance", [](auto& s) { s.newton_tolerance = 0; }},
      {"newton_tolerance", [nan](auto& s) { s.newton_tolerance = nan; }},
      {"linear_tolerance", [](auto& s) { s.linear_tolerance = -1e-3; }},
      {"linear_tolerance", [](auto& s) { s.linear_tolerance = 1; }},
      {"derivative_step", [](auto& s) { s.derivative_step = 0; }},
      {"derivative_step", [](auto& s) { s.derivative_step = std::numeric_limits<double>::infinity(); }},
      {"restart", [](auto& s) { s.restart = 0; }},
      {"max_newton", [](auto& s) { s.max_newton = 0; }},
      {"max_krylov", [](auto& s) { s.max_krylov = -3; }},
      {"max_backtracks", [](auto& s) { s.max_backtracks = -1; }},
      {"refresh_after", [](auto& s) { s.refresh_after = -1; }},
      {"krylov", [](auto& s) { s.krylov = nk::Krylov::direct; }},
  };
  for (const Case& c : cases) {
    nk::NewtonSettings s;
    c.spoil(s);
    const std::string message = validation_error(s);
    EXPECT_EQ(message.rfind(std::string("scene.toml: [implicit] ") + c.key + ": expected ", 0), 0u)
        << message;
    Vector x = Vector::Zero(2);
    Componentwise f = arctan(2);
    EXPECT_THROW(nk::solve(f, x, s), mpm::InputError) << c.key;
    EXPECT_EQ(f.residual_calls, 0);
  }
  nk::NewtonSettings s;
  s.restart = 0;
  EXPECT_EQ(validation_error(s), "scene.toml: [implicit] restart: expected an integer >= 1, got 0");
  s = {};
  s.max_backtracks = 0;  // allowed: no halving, the full step must decrease ||F||
  EXPECT_EQ(validation_error(s), "");
}

}  // namespace

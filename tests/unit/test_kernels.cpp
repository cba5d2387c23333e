// One-dimensional shape-function policies (mpm/shape/kernels.hpp) and their tensor products (stencil.hpp).
//
// Every kernel is checked for partition of unity, zero gradient sum, linear reproduction, non-negativity and
// continuity across the positions where its base node changes. GIMP is checked against the defining
// convolution (Wallstedt & Guilkey 2008, Eq. 1 with Eqs 2 and 4) and its gradient against a central
// difference; the B-splines against their closed forms; and the limits of Steffen et al. 2008, Sec. 4.1 (l_p
// -> 0 gives the linear hat, l_p = h/2 gives the quadratic B-spline). All positions are in grid units (h = 1)
// unless stated otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "mpm/grid/grid.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"

namespace {

using mpm::Real;
constexpr Real kEps = std::numeric_limits<Real>::epsilon();

// Sums of at most four weights (or gradients, all bounded by 1 in grid units) each carrying a few roundings:
// 1e-14 is ~45 ulps of 1.
constexpr Real kSumTol = 1e-14;

// The GIMP half-lengths l_p/h tested, spanning (0, 1/2], and (0, 1] for the wide stencil.
const std::vector<Real> kGimpHalfLengths = {0.05, 0.125, 0.25, 0.4, 0.5};
const std::vector<Real> kWideGimpHalfLengths = {0.05, 0.25, 0.5, 0.6, 0.75, 0.9, 1.0};

// Weights, gradients and base node of one kernel at one position.
template <class Kernel>
struct Weights {
  int base = 0;
  std::array<Real, Kernel::width> w{}, dw{};
};

template <class Kernel>
Weights<Kernel> evaluate(Real xi, Real half_length) {
  Weights<Kernel> s;
  s.base = Kernel::weights(xi, half_length, s.w.data(), s.dw.data());
  return s;
}

// Weight and gradient of global node `node` (zero when outside the stencil).
template <class Kernel>
std::array<Real, 2> node_weight(Real xi, Real half_length, int node) {
  const Weights<Kernel> s = evaluate<Kernel>(xi, half_length);
  const int k = node - s.base;
  if (k < 0 || k >= Kernel::width) return {0, 0};
  return {s.w[k], s.dw[k]};
}

// The half-lengths to test a kernel with. Non-GIMP kernels ignore the argument: a NaN would poison their
// weights if it were read.
template <class Kernel>
std::vector<Real> half_lengths_for() {
  if constexpr (std::is_same_v<Kernel, mpm::GimpKernel>)
    return kGimpHalfLengths;
  else if constexpr (std::is_same_v<Kernel, mpm::WideGimpKernel>)
    return kWideGimpHalfLengths;
  else
    return {std::numeric_limits<Real>::quiet_NaN()};
}

// Positions in grid units: every 1/16 over [-3, 5] (nodes, half-nodes and, for the l_p above, the exact GIMP
// branch points), points within a few ulps of nodes and half-nodes (where the base node switches), and
// pseudo-random points (fixed seed).
std::vector<Real> sample_positions() {
  std::vector<Real> xs;
  for (int k = -48; k <= 80; ++k) xs.push_back(k / 16.0);
  for (int k = -4; k <= 8; ++k) {
    const Real x = k / 2.0;
    xs.push_back(std::nextafter(x, -10.0));
    xs.push_back(std::nextafter(x, 10.0));
    xs.push_back(x - 0x1p-50);  // a few ulps off: 8.9e-16
    xs.push_back(x + 0x1p-50);
  }
  std::mt19937_64 rng(20080101);
  std::uniform_real_distribution<Real> u(-3.0, 5.0);
  for (int k = 0; k < 256; ++k) xs.push_back(u(rng));
  return xs;
}

// Linear hat of Wallstedt & Guilkey 2008, Eq. (2), at signed distance r (grid units).
Real hat(Real r) {
  return std::max<Real>(0, 1 - std::abs(r));
}

// Wallstedt & Guilkey 2008, Eq. (1) with the top-hat of Eq. (4) normalised by V_p = 2 l_p:
//   S_i(x_p) = (1/(2 l_p)) * integral_{x_p-l_p}^{x_p+l_p} S_i(x) dx,   r = x_p - x_i.
// The integrand is linear between its kinks {-1, 0, 1}, so the trapezoid rule on each piece is exact and the
// only error is round-off.
Real hat_average(Real r, Real l) {
  const Real b = r + l;
  Real u = r - l, integral = 0;
  for (Real kink : {-1.0, 0.0, 1.0})
    if (kink > u && kink < b) {
      integral += (kink - u) * (hat(u) + hat(kink)) / 2;
      u = kink;
    }
  integral += (b - u) * (hat(u) + hat(b)) / 2;
  return integral / (2 * l);
}

// ---------------------------------------------------------------------------------------------------------------
// Properties shared by every kernel.

template <class Kernel>
class KernelTest : public ::testing::Test {};

using Kernels = ::testing::Types<mpm::LinearKernel, mpm::GimpKernel, mpm::WideGimpKernel,
                                 mpm::QuadraticBSplineKernel, mpm::CubicBSplineKernel>;

struct KernelName {
  template <class Kernel>
  static std::string GetName(int) {
    return Kernel::name;
  }
};
TYPED_TEST_SUITE(KernelTest, Kernels, KernelName);

/// Call fn(s) with the weights at every sample position and half-length, traced.
template <class Kernel, class Fn>
void for_each_sample(Fn&& fn) {
  for (Real l : half_lengths_for<Kernel>())
    for (Real xi : sample_positions()) {
      SCOPED_TRACE(::testing::Message() << "l_p/h = " << l << ", xi = " << xi);
      fn(evaluate<Kernel>(xi, l), xi);
    }
}

TYPED_TEST(KernelTest, partition_of_unity_and_zero_gradient_sum) {
  using Kernel = TypeParam;
  for_each_sample<Kernel>([&](const Weights<Kernel>& s, [[maybe_unused]] Real xi) {
    Real sum_w = 0, sum_dw = 0;
    for (int k = 0; k < Kernel::width; ++k) {
      sum_w += s.w[k];
      sum_dw += s.dw[k];
    }
    EXPECT_NEAR(sum_w, 1.0, kSumTol);
    EXPECT_NEAR(sum_dw, 0.0, kSumTol);
  });
}

TYPED_TEST(KernelTest, weights_are_non_negative) {
  using Kernel = TypeParam;
  for_each_sample<Kernel>([&](const Weights<Kernel>& s, [[maybe_unused]] Real xi) {
    // Exact: evaluated on its own interval (kernels.hpp: r = xi - base in [0, 1) or [0.5, 1.5)), every
    // branch is a square or bounded away from zero.
    for (int k = 0; k < Kernel::width; ++k) EXPECT_GE(s.w[k], 0.0) << "node " << s.base + k;
  });
}

TYPED_TEST(KernelTest, reproduces_linear_functions) {
  using Kernel = TypeParam;
  for_each_sample<Kernel>([&](const Weights<Kernel>& s, [[maybe_unused]] Real xi) {
    Real x = 0, dx = 0;
    for (int k = 0; k < Kernel::width; ++k) {
      x += s.w[k] * (s.base + k);
      dx += s.dw[k] * (s.base + k);
    }
    // Round-off of <= 4 products of node coordinates (|x_i| <= 7) with weights or gradients bounded by 1.
    const Real tol = 8 * Kernel::width * kEps * (1 + std::abs(xi));
    EXPECT_NEAR(x, xi, tol);
    EXPECT_NEAR(dx, 1.0, tol);
  });
}

TYPED_TEST(KernelTest, node_weights_are_continuous_where_the_base_node_switches) {
  using Kernel = TypeParam;
  for (Real l : half_lengths_for<Kernel>())
    for (int k = -4; k <= 8; ++k) {
      // The base node switches at nodes (linear, cubic) or half-nodes (GIMP, quadratic): compare every node's
      // weight on the two floating-point neighbours of each.
      const Real x = k / 2.0;
      const Real below = std::nextafter(x, -10.0), above = std::nextafter(x, 10.0);
      SCOPED_TRACE(::testing::Message() << "l_p/h = " << l << ", xi = " << x);
      const int first = static_cast<int>(std::floor(x)) - Kernel::width;
      for (int node = first; node <= first + 2 * Kernel::width; ++node) {
        // The weights are Lipschitz with constant 1, so a 2-ulp step changes them by ~1e-15 plus round-off.
        EXPECT_NEAR(node_weight<Kernel>(below, l, node)[0], node_weight<Kernel>(above, l, node)[0], kSumTol)
            << "node " << node;
      }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// GIMP: closed form (Wallstedt & Guilkey 2008, Eqs 5-6) against its definition, for several half-lengths.

template <class Kernel>
void expect_closed_form_equals_convolution(Real l) {
  // The end points x_p -+ l_p are rounded (|r| <= 2.5, error <= eps), which moves the integral of a function
  // bounded by 1 by ~2 eps and the average by ~eps/l_p; the closed form itself is a few ulps.
  const Real tol = 8 * kEps * (1 + 1 / l);
  for (Real xi : sample_positions()) {
    SCOPED_TRACE(::testing::Message() << "xi = " << xi);
    const Weights<Kernel> s = evaluate<Kernel>(xi, l);
    for (int k = 0; k < Kernel::width; ++k)
      EXPECT_NEAR(s.w[k], hat_average(xi - (s.base + k), l), tol)
          << "node " << s.base + k;  // Eq. (5) vs Eq. (1)
    // The stencil holds the whole support |x_p - x_i| < h + l_p: the neighbours just outside it get nothing.
    // (Not exactly: within an ulp of a half-node, xi - 1/2 rounds onto the integer and the base node moves
    // one node early, dropping a node whose exact weight is O(eps^2), e.g. 2.5e-32 at xi = -1.5 - ulp; that
    // is far below round-off, so the same tolerance applies.)
    EXPECT_NEAR(hat_average(xi - (s.base - 1), l), 0.0, tol);
    EXPECT_NEAR(hat_average(xi - (s.base + Kernel::width), l), 0.0, tol);
  }
}

template <class Kernel>
void expect_gradient_equals_central_difference(Real l) {
  // Step e = 2^-14. The central-difference error is e^2/6 S''' + O(e^4), and S''' = 0 on each quadratic piece
  // of Eq. (5), so away from the branch points only round-off remains: ~(4 eps + 2 ulp(xi)) / (2 e) ~ 2e-11,
  // hence 1e-9. Within e of a branch point the C^1 weight has a jump in S'' of at most 3/(2 l_p) (at l_p =
  // 1/2 two branch points merge), bounding the error by 3 e / (8 l_p).
  const Real e = std::ldexp(1.0, -14);
  const std::array<Real, 6> branch_points = {-1 - l, -1 + l, -l, l, 1 - l, 1 + l};  // Eqs (5)-(6)
  for (Real xi : sample_positions()) {
    SCOPED_TRACE(::testing::Message() << "xi = " << xi);
    const Weights<Kernel> s = evaluate<Kernel>(xi, l);
    for (int k = 0; k < Kernel::width; ++k) {
      const int node = s.base + k;
      const Real r = xi - node;
      bool near_branch = false;
      for (Real b : branch_points) near_branch = near_branch || std::abs(r - b) < e;
      const Real tol = 1e-9 + (near_branch ? 3 * e / (8 * l) : 0);
      const Real central =
          (node_weight<Kernel>(xi + e, l, node)[0] - node_weight<Kernel>(xi - e, l, node)[0]) / (2 * e);
      EXPECT_NEAR(s.dw[k], central, tol) << "node " << node;  // Eq. (6)
    }
  }
}

class GimpHalfLength : public ::testing::TestWithParam<Real> {};
INSTANTIATE_TEST_SUITE_P(kernels, GimpHalfLength, ::testing::ValuesIn(kGimpHalfLengths));

TEST_P(GimpHalfLength, closed_form_equals_convolution_of_hat_and_top_hat) {
  expect_closed_form_equals_convolution<mpm::GimpKernel>(GetParam());
}

TEST_P(GimpHalfLength, gradient_equals_central_difference_of_weight) {
  expect_gradient_equals_central_difference<mpm::GimpKernel>(GetParam());
}

// The wide stencil: half-lengths up to a cell, where the support reaches 4 nodes (l_p > 1/2).
class WideGimpHalfLength : public ::testing::TestWithParam<Real> {};
INSTANTIATE_TEST_SUITE_P(kernels, WideGimpHalfLength, ::testing::ValuesIn(kWideGimpHalfLengths));

TEST_P(WideGimpHalfLength, closed_form_equals_convolution_of_hat_and_top_hat) {
  expect_closed_form_equals_convolution<mpm::WideGimpKernel>(GetParam());
}

TEST_P(WideGimpHalfLength, gradient_equals_central_difference_of_weight) {
  expect_gradient_equals_central_difference<mpm::WideGimpKernel>(GetParam());
}

TEST_P(WideGimpHalfLength, equals_the_narrow_stencil_where_both_hold) {
  // l_p <= 1/2: the same closed form on one node more, which gets 0; node by node to a few ulps (the wide
  // kernel evaluates both corrections on every node, the narrow one only the one that can be non-zero).
  const Real l = GetParam();
  if (l > 0.5) GTEST_SKIP() << "the narrow stencil holds l_p <= 1/2";
  for (Real xi : sample_positions())
    for (int node = static_cast<int>(std::floor(xi)) - 2; node <= static_cast<int>(std::floor(xi)) + 3;
         ++node) {
      const auto wide = node_weight<mpm::WideGimpKernel>(xi, l, node);
      const auto narrow = node_weight<mpm::GimpKernel>(xi, l, node);
      EXPECT_NEAR(wide[0], narrow[0], 4 * kEps) << "xi = " << xi << ", node " << node;
      EXPECT_NEAR(wide[1], narrow[1], 4 * kEps / l) << "xi = " << xi << ", node " << node;
    }
}

// ---------------------------------------------------------------------------------------------------------------
// The limits of Steffen et al. 2008, Sec. 4.1.

TEST(gimp_limits, vanishing_half_length_gives_linear_hat) {
  // Smoothing the hat (slope jumps 2 at its peak, 1 at its feet) with a top-hat of half-length l_p changes it
  // by at most l_p/2, attained at the nodes (1 - l_p/2 in Eq. 5); the rest is a few ulps of round-off.
  for (Real l : {1e-3, 1e-5, 1e-7}) {
    SCOPED_TRACE(::testing::Message() << "l_p/h = " << l);
    Real max_diff = 0;
    for (Real xi : sample_positions()) {
      const int first = static_cast<int>(std::floor(xi)) - 2;
      for (int node = first; node <= first + 5; ++node) {
        const Real diff = std::abs(node_weight<mpm::GimpKernel>(xi, l, node)[0] -
                                   node_weight<mpm::LinearKernel>(xi, l, node)[0]);
        EXPECT_LE(diff, l / 2 + 8 * kEps) << "xi = " << xi << ", node " << node;
        max_diff = std::max(max_diff, diff);
      }
    }
    EXPECT_NEAR(max_diff, l / 2, 8 * kEps);  // the difference is O(l_p), not smaller
  }
}

TEST(gimp_limits, half_length_of_half_a_cell_gives_quadratic_bspline) {
  for (Real xi : sample_positions()) {
    SCOPED_TRACE(::testing::Message() << "xi = " << xi);
    const Weights<mpm::GimpKernel> g = evaluate<mpm::GimpKernel>(xi, 0.5);
    const Weights<mpm::QuadraticBSplineKernel> b = evaluate<mpm::QuadraticBSplineKernel>(xi, 0.5);
    ASSERT_EQ(g.base, b.base);
    for (int k = 0; k < 3; ++k) {
      // The same quadratic polynomials evaluated in a different order: a few ulps of values bounded by 1.
      EXPECT_NEAR(g.w[k], b.w[k], 4 * kEps);
      EXPECT_NEAR(g.dw[k], b.dw[k], 4 * kEps);
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// B-splines against their closed forms (uniform B-splines built by repeated convolution of the cell-wide
// top-hat, Steffen et al. 2008, Eq. 19), q = |x_p - x_i| / h.

// Value and derivative with respect to r = x_p - x_i of the closed form N(q), given N(q) and dN/dq.
template <class Closed>
std::array<Real, 2> radial(Real r, Closed closed) {
  const auto [n, dn] = closed(std::abs(r));
  return {n, r < 0 ? -dn : dn};
}

std::array<Real, 2> quadratic_closed_form(Real q) {
  if (q < 0.5) return {0.75 - q * q, -2 * q};
  if (q < 1.5) return {0.5 * (1.5 - q) * (1.5 - q), -(1.5 - q)};
  return {0, 0};
}

std::array<Real, 2> cubic_closed_form(Real q) {
  if (q < 1) return {0.5 * q * q * q - q * q + 2.0 / 3.0, 1.5 * q * q - 2 * q};
  if (q < 2) return {(2 - q) * (2 - q) * (2 - q) / 6, -0.5 * (2 - q) * (2 - q)};
  return {0, 0};
}

template <class Kernel, class Closed>
void expect_closed_form(Closed closed) {
  for (Real xi : sample_positions()) {
    SCOPED_TRACE(::testing::Message() << "xi = " << xi);
    const Weights<Kernel> s = evaluate<Kernel>(xi, 0.5);
    for (int k = 0; k < Kernel::width; ++k) {
      const auto [n, dn] = radial(xi - (s.base + k), closed);
      // Cubic polynomials with coefficients <= 2 in q <= 2, evaluated in a different order: ~10 ulps of 1.
      EXPECT_NEAR(s.w[k], n, 16 * kEps) << "node " << s.base + k;
      EXPECT_NEAR(s.dw[k], dn, 16 * kEps) << "node " << s.base + k;
    }
  }
}

TEST(bspline, quadratic_matches_closed_form) {
  expect_closed_form<mpm::QuadraticBSplineKernel>(quadratic_closed_form);
}

TEST(bspline, cubic_matches_closed_form) {
  expect_closed_form<mpm::CubicBSplineKernel>(cubic_closed_form);
}

TEST(bspline, quadratic_is_hat_convolved_with_cell_wide_top_hat) {
  // Steffen et al. 2008, Sec. 4.1: the quadratic B-spline is the linear hat convolved with a top-hat of width
  // h (half-width h/2). Exact piecewise integration: round-off only, as for GIMP with l_p = 1/2 (8 eps (1 +
  // 2)).
  for (Real xi : sample_positions()) {
    SCOPED_TRACE(::testing::Message() << "xi = " << xi);
    const Weights<mpm::QuadraticBSplineKernel> s = evaluate<mpm::QuadraticBSplineKernel>(xi, 0.5);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.w[k], hat_average(xi - (s.base + k), 0.5), 24 * kEps);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Multi-D tensor products through make_stencil and for_each_node (Wallstedt & Guilkey 2008, Sec. 2: multi-D
// shape functions are tensor products of the 1-D ones), on a grid with h != 1 and an offset origin.

template <int Dim, class Kernel>
void expect_tensor_product_properties() {
  mpm::GridGeometry<Dim> geo;
  const std::array<Real, 3> origin = {-0.35, 0.2, 1.1};
  for (int d = 0; d < Dim; ++d) geo.lo[d] = origin[d];
  geo.h = 0.1;
  geo.cells.fill(6);
  geo.ghost = Kernel::ghost;
  const mpm::NodeLayout<Dim> strides(geo);
  const mpm::Vec<Dim> hi = geo.hi();

  std::mt19937_64 rng(4242 + Dim);
  std::uniform_real_distribution<Real> unit(0.0, 1.0), half_length(0.05 * geo.h, 0.5 * geo.h);
  for (int sample = 0; sample < 200; ++sample) {
    mpm::Vec<Dim> x, l;
    for (int d = 0; d < Dim; ++d) {
      x[d] = geo.lo[d] + unit(rng) * (hi[d] - geo.lo[d]);  // anywhere in the physical domain
      l[d] = half_length(rng);
    }
    if (sample == 0) x = geo.lo;  // domain corners: the stencil reaches the ghost layers
    if (sample == 1) x = hi;
    SCOPED_TRACE(::testing::Message() << "x = " << x.transpose());
    const auto s = mpm::make_stencil<Dim, Kernel>(geo, strides, x, l);

    Real sum_w = 0, max_abs_x = 0;
    mpm::Vec<Dim> sum_dw = mpm::Vec<Dim>::Zero(), sum_wx = mpm::Vec<Dim>::Zero();
    mpm::Mat<Dim> sum_x_dw = mpm::Mat<Dim>::Zero();
    int visited = 0;
    mpm::for_each_node(s, strides, [&](std::int32_t n, Real w, const mpm::Vec<Dim>& dw) {
      ASSERT_GE(n, 0);
      ASSERT_LT(static_cast<std::size_t>(n), geo.node_count());
      const mpm::Vec<Dim> xn = geo.position(geo.coords(n));
      max_abs_x = std::max(max_abs_x, xn.cwiseAbs().maxCoeff());
      sum_w += w;
      sum_dw += dw;
      sum_wx += w * xn;
      sum_x_dw += xn * dw.transpose();
      ++visited;
    });
    int expected_nodes = 1;
    for (int d = 0; d < Dim; ++d) expected_nodes *= Kernel::width;
    EXPECT_EQ(visited, expected_nodes);
    // Products of Dim weights summing to 1: a few ulps per factor and per term.
    EXPECT_NEAR(sum_w, 1.0, kSumTol);
    // Gradients are per metre, bounded by 1/h.
    for (int d = 0; d < Dim; ++d) EXPECT_NEAR(sum_dw[d], 0.0, kSumTol / geo.h);
    // Linear reproduction sum S_i x_i = x, sum x_i (grad S_i)^T = I: round-off of width^Dim terms of size
    // |x_i| (resp. |x_i| / h).
    const Real tol = expected_nodes * 2 * kEps * max_abs_x;
    for (int a = 0; a < Dim; ++a) {
      EXPECT_NEAR(sum_wx[a], x[a], tol);
      for (int b = 0; b < Dim; ++b) EXPECT_NEAR(sum_x_dw(a, b), a == b ? 1.0 : 0.0, tol / geo.h);
    }
  }
}

TYPED_TEST(KernelTest, tensor_product_2d) {
  expect_tensor_product_properties<2, TypeParam>();
}

TYPED_TEST(KernelTest, tensor_product_3d) {
  expect_tensor_product_properties<3, TypeParam>();
}

}  // namespace

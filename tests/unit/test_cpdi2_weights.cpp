// The CPDI2 domain weights (shape/cpdi2.hpp; Sadeghirad, Brannon & Guilkey 2013): exact against a 4-point
// Gauss rule for random quadrilaterals and hexahedra, CPDI's for parallelograms, and the properties the
// transfers need.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "mpm/shape/cpdi2.hpp"

namespace {
using mpm::Real;

template <int Dim>
using Corners = Real[1 << Dim][Dim];

/// A unit cube's corners (half-width 1/2 about 0.3) moved by up to `size` each.
template <int Dim>
void random_domain(std::mt19937_64& rng, Real size, Corners<Dim>& x) {
  std::uniform_real_distribution<Real> u(-size, size);
  for (int c = 0; c < (1 << Dim); ++c)
    for (int d = 0; d < Dim; ++d) x[c][d] = 0.3 + 0.5 * mpm::CpdiKernel<Dim>::sign(c, d) + u(rng);
}

/// V, int M_c dV and int grad M_c dV by the 4-point Gauss rule per axis with the inverse Jacobian (a
/// different and more accurate route than the class's 2-point rule with cofactors).
template <int Dim>
struct Reference {
  static constexpr int C = 1 << Dim;
  Real V = 0, w[C] = {}, g[C][Dim] = {};
  explicit Reference(const Corners<Dim>& x) {
    const std::array<Real, 4> p = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                   0.8611363115940526};
    const std::array<Real, 4> pw = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                    0.3478548451374538};
    const int points = Dim == 2 ? 16 : 64;
    for (int q = 0; q < points; ++q) {
      Real xi[Dim], weight = 1;
      for (int k = 0, rest = q; k < Dim; ++k, rest /= 4) {
        xi[k] = p[rest % 4];
        weight *= pw[rest % 4];
      }
      Real M[C], dM[C][Dim];
      for (int c = 0; c < C; ++c) {
        M[c] = 1;
        for (int k = 0; k < Dim; ++k) M[c] *= 0.5 * (1 + mpm::CpdiKernel<Dim>::sign(c, k) * xi[k]);
        for (int k = 0; k < Dim; ++k) {
          dM[c][k] = 0.5 * mpm::CpdiKernel<Dim>::sign(c, k);
          for (int j = 0; j < Dim; ++j)
            if (j != k) dM[c][k] *= 0.5 * (1 + mpm::CpdiKernel<Dim>::sign(c, j) * xi[j]);
        }
      }
      mpm::Mat<Dim> J = mpm::Mat<Dim>::Zero();
      for (int d = 0; d < Dim; ++d)
        for (int k = 0; k < Dim; ++k)
          for (int c = 0; c < C; ++c) J(d, k) += dM[c][k] * x[c][d];
      const Real det = J.determinant();
      const mpm::Mat<Dim> inv_T = J.inverse().transpose();
      V += weight * det;
      for (int c = 0; c < C; ++c) {
        w[c] += weight * M[c] * det;
        mpm::Vec<Dim> grad_xi;
        for (int k = 0; k < Dim; ++k) grad_xi[k] = dM[c][k];
        const mpm::Vec<Dim> grad = inv_T * grad_xi;
        for (int d = 0; d < Dim; ++d) g[c][d] += weight * grad[d] * det;
      }
    }
    for (int c = 0; c < C; ++c) {
      w[c] /= V;
      for (int d = 0; d < Dim; ++d) g[c][d] /= V;
    }
  }
};

template <int Dim>
void expect_exact_and_consistent() {
  std::mt19937_64 rng(41 + Dim);
  for (int sample = 0; sample < 200; ++sample) {
    Corners<Dim> x;
    random_domain<Dim>(rng, 0.2, x);
    const mpm::CornerDomain<Dim, Real> domain(x);
    const Reference<Dim> ref(x);
    EXPECT_NEAR(domain.V, ref.V, 1e-14);
    Real sum_w = 0;
    mpm::Vec<Dim> sum_g = mpm::Vec<Dim>::Zero();
    mpm::Mat<Dim> xg = mpm::Mat<Dim>::Zero();
    for (int c = 0; c < (1 << Dim); ++c) {
      EXPECT_NEAR(domain.w[c], ref.w[c], 1e-14);
      sum_w += domain.w[c];
      for (int d = 0; d < Dim; ++d) {
        EXPECT_NEAR(domain.g[c][d], ref.g[c][d], 1e-13);
        sum_g[d] += domain.g[c][d];
        for (int e = 0; e < Dim; ++e) xg(d, e) += x[c][d] * domain.g[c][e];
      }
    }
    EXPECT_NEAR(sum_w, 1, 1e-14);
    EXPECT_LT(sum_g.norm(), 1e-13);
    EXPECT_LT((xg - mpm::Mat<Dim>::Identity()).norm(), 1e-13);
  }
}

TEST(Cpdi2Weights, TwoPointGaussIsExactForQuadrilaterals) {
  expect_exact_and_consistent<2>();
}
TEST(Cpdi2Weights, TwoPointGaussIsExactForHexahedra) {
  expect_exact_and_consistent<3>();
}

TEST(Cpdi2Weights, ParallelogramsGiveCpdisWeights) {
  // Corners x_p + R s_c: w_c = 2^-D and g_c = 2^-D R^-T s_c (shape/cpdi.hpp).
  mpm::Mat<3> R;
  R << 0.3, 0.1, -0.05, 0.02, 0.25, 0.1, -0.07, 0.04, 0.2;
  Corners<3> x;
  for (int c = 0; c < 8; ++c)
    for (int d = 0; d < 3; ++d) {
      x[c][d] = 1.0;
      for (int k = 0; k < 3; ++k) x[c][d] += R(d, k) * mpm::CpdiKernel<3>::sign(c, k);
    }
  const mpm::CornerDomain<3, Real> domain(x);
  const mpm::Mat<3> G = R.inverse().transpose() / 8;
  EXPECT_NEAR(domain.V, 8 * R.determinant(), 1e-15);
  for (int c = 0; c < 8; ++c) {
    EXPECT_NEAR(domain.w[c], 0.125, 1e-15);
    mpm::Vec<3> s;
    for (int k = 0; k < 3; ++k) s[k] = mpm::CpdiKernel<3>::sign(c, k);
    const mpm::Vec<3> g = G * s;
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(domain.g[c][d], g[d], 1e-14);
  }
}

TEST(Cpdi2Weights, QuadrilateralWeightsFollowTheTriangleAreas) {
  // 2-D closed form with the corners counter-clockwise: w_c = 1/4 + (T_c - T_{c+2}) / (12 V), T_c the signed
  // area of the triangle (c-1, c, c+1); V the shoelace area. Bit order (-,-), (+,-), (-,+), (+,+) is ccw
  // order 0, 1, 3, 2.
  std::mt19937_64 rng(3);
  const int ccw[4] = {0, 1, 3, 2};
  for (int sample = 0; sample < 100; ++sample) {
    Corners<2> x;
    random_domain<2>(rng, 0.25, x);
    const mpm::CornerDomain<2, Real> domain(x);
    auto at = [&](int k) { return mpm::Vec<2>(x[ccw[(k + 4) % 4]][0], x[ccw[(k + 4) % 4]][1]); };
    Real V = 0;
    for (int k = 0; k < 4; ++k) V += 0.5 * (at(k)[0] * at(k + 1)[1] - at(k + 1)[0] * at(k)[1]);
    EXPECT_NEAR(domain.V, V, 1e-15);
    auto T = [&](int k) {
      const mpm::Vec<2> a = at(k) - at(k - 1), b = at(k + 1) - at(k);
      return 0.5 * (a[0] * b[1] - a[1] * b[0]);
    };
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(domain.w[ccw[k]], 0.25 + (T(k) - T(k + 2)) / (12 * V), 1e-15);
  }
}

}  // namespace

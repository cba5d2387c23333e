// B-splines whose knots are clamped at the grid's faces (GridGeometry::clamped, stencil.hpp's locate_axis,
// kernels.hpp's weights_at; Steffen et al. 2008, Sec. 4.3): the ghost node's function folded into the face's
// two nodes by linear extrapolation (N_0 + 2 N_-1, N_1 - N_-1). Checked on grids of few cells clamped at both
// faces: no stencil reaches beyond a face; partition of unity, zero gradient sum and linear reproduction up
// to the faces; non-negative, continuous weights; the closed forms of the folded functions and their
// integrals; the uniform weights unchanged away from the faces; lanes equal to the one-particle path; and the
// 2-D and 3-D tensor products at the domain's corners. Positions in grid units (h = 1) unless stated
// otherwise.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"

namespace {

using mpm::Real;
constexpr Real kEps = std::numeric_limits<Real>::epsilon();
constexpr Real kSumTol = 1e-14;  // sums of at most four weights of a few roundings each (~45 ulps of 1)

template <class Kernel>
struct Located {
  int base = 0;
  std::array<Real, Kernel::width> w{}, dw{};
};

/// A 1-D grid of `cells` unit cells, clamped at both faces (or none).
mpm::GridGeometry<1> grid(int cells, int ghost, bool clamped = true) {
  mpm::GridGeometry<1> g{mpm::Vec<1>(0.0), 1.0, {cells}, ghost};
  g.clamped = {clamped, clamped};
  return g;
}

template <class Kernel>
[[gnu::noinline]] Located<Kernel> locate(const mpm::GridGeometry<1>& g, Real xi) {
  Located<Kernel> s;
  typename Kernel::Axis a;
  s.base = mpm::locate_axis<Kernel>(g, 0, xi, Real(0), a);
  Kernel::weights_at(a, s.w.data(), s.dw.data());
  return s;
}

/// Weight and gradient of node `node` at xi (zero outside the stencil).
template <class Kernel>
std::array<Real, 2> node_weight(const mpm::GridGeometry<1>& g, Real xi, int node) {
  const Located<Kernel> s = locate<Kernel>(g, xi);
  const int k = node - s.base;
  if (k < 0 || k >= Kernel::width) return {0, 0};
  return {s.w[k], s.dw[k]};
}

template <class Kernel>
class ClampedKernel : public ::testing::Test {};
using Kernels = ::testing::Types<mpm::QuadraticBSplineKernel, mpm::CubicBSplineKernel>;
TYPED_TEST_SUITE(ClampedKernel, Kernels);

/// The fewest cells a clamped spline spans (validate_clamped_cells) and a few more.
template <class Kernel>
std::vector<int> cell_counts() {
  return {Kernel::width - 1, Kernel::width, 7};
}

TYPED_TEST(ClampedKernel, PartitionOfUnityAndLinearReproductionUpToTheFaces) {
  using K = TypeParam;
  for (int n : cell_counts<K>()) {
    const mpm::GridGeometry<1> g = grid(n, K::ghost);
    for (int k = 0; k <= 400 * n; ++k) {
      const Real xi = n * (k / (400.0 * n));  // 0 and n exactly included
      SCOPED_TRACE(::testing::Message() << n << " cells, xi = " << xi);
      const Located<K> s = locate<K>(g, xi);
      ASSERT_GE(s.base, 0);                 // no node below the lower face
      ASSERT_LE(s.base + K::width - 1, n);  // nor above the upper one
      Real sum_w = 0, sum_dw = 0, sum_xw = 0, sum_xdw = 0;
      for (int j = 0; j < K::width; ++j) {
        EXPECT_GE(s.w[j], -kEps);
        sum_w += s.w[j];
        sum_dw += s.dw[j];
        sum_xw += (s.base + j) * s.w[j];
        sum_xdw += (s.base + j) * s.dw[j];
      }
      EXPECT_NEAR(sum_w, 1.0, kSumTol);
      EXPECT_NEAR(sum_dw, 0.0, kSumTol);
      EXPECT_NEAR(sum_xw, xi, n * kSumTol);  // terms of size |x_i| <= n
      EXPECT_NEAR(sum_xdw, 1.0, n * kSumTol);
    }
  }
}

TYPED_TEST(ClampedKernel, WeightsAreContinuousAndGradientsAreTheirDerivatives) {
  // Each node's weight evaluated just left and right of every half-integer (where the pieces and the base
  // node change): the jump is the slope times the 2e-9 step, < 1e-8. Its gradient against a central
  // difference of step 1e-6 away from the breaks: the truncation error is O(1e-12) times the third derivative
  // (<= 4), and the difference's round-off 1e-16 / 1e-6.
  using K = TypeParam;
  const int n = 7;
  const mpm::GridGeometry<1> g = grid(n, K::ghost);
  for (int node = 0; node <= n; ++node) {
    for (int b = 0; b <= 2 * n; ++b) {
      const Real at = 0.5 * b;
      const Real left = at > 0 ? node_weight<K>(g, at - 1e-9, node)[0] : node_weight<K>(g, 0, node)[0];
      const Real right = at < n ? node_weight<K>(g, at + 1e-9, node)[0] : node_weight<K>(g, n, node)[0];
      EXPECT_NEAR(left, right, 1e-8) << "node " << node << " at " << at;
    }
    for (int k = 0; k < 20 * n; ++k) {
      const Real xi = (k + 0.37) / 20.0;
      const Real fd = (node_weight<K>(g, xi + 1e-6, node)[0] - node_weight<K>(g, xi - 1e-6, node)[0]) / 2e-6;
      EXPECT_NEAR(node_weight<K>(g, xi, node)[1], fd, 1e-8) << "node " << node << " at " << xi;
    }
  }
}

/// The folded functions of the face's nodes in closed form, q the distance to the face (Steffen et al. 2008,
/// Sec. 4.3; the uniform functions of Sec. 3.3 folded by linear extrapolation, derived in docs/transfers.md).
Real folded(int width, int node, Real q) {
  if (width == 3) {
    if (node == 0) return q < 0.5 ? 1 - q : q < 1.5 ? 0.5 * (1.5 - q) * (1.5 - q) : 0;
    if (node == 1)
      return q < 0.5 ? q : q < 1.5 ? 0.75 - (q - 1) * (q - 1) : q < 2.5 ? 0.5 * (2.5 - q) * (2.5 - q) : 0;
  } else {
    if (node == 0) return q < 1 ? 1 - q + q * q * q / 6 : q < 2 ? (2 - q) * (2 - q) * (2 - q) / 6 : 0;
    if (node == 1) {
      const Real s = q - 1;
      return q < 1   ? q - q * q * q / 3
             : q < 2 ? 2.0 / 3 - s * s + s * s * s / 2
             : q < 3 ? (3 - q) * (3 - q) * (3 - q) / 6
                     : 0;
    }
  }
  return std::numeric_limits<Real>::quiet_NaN();
}

TYPED_TEST(ClampedKernel, FaceNodesFollowTheFoldedClosedFormsAtBothFaces) {
  // Polynomials of degree <= 3 in q <= n evaluated two ways: a few ulps of the terms (<= 9).
  using K = TypeParam;
  const int n = 7;
  const mpm::GridGeometry<1> g = grid(n, K::ghost);
  for (int k = 0; k <= 700; ++k) {
    const Real q = k / 100.0;
    for (int node = 0; node < 2; ++node) {
      EXPECT_NEAR(node_weight<K>(g, q, node)[0], folded(K::width, node, q), 16 * kEps)
          << "lower, node " << node << ", q " << q;
      EXPECT_NEAR(node_weight<K>(g, n - q, n - node)[0], folded(K::width, node, q), 16 * kEps * n)
          << "upper, node " << n - node << ", q " << q;
    }
  }
  // The face node interpolates: weight 1 on its own face, so a wall's velocity is the particles' there.
  EXPECT_EQ(node_weight<K>(g, 0, 0)[0], 1.0);
  EXPECT_EQ(node_weight<K>(g, n, n)[0], 1.0);
}

TYPED_TEST(ClampedKernel, FaceNodesIntegrateToTheirLumpedShares) {
  // int N_0 = 13/24, int N_1 = 23/24 (quadratic), 7/12 and 11/12 (cubic), every other node 1 (derived from
  // the closed forms). Simpson's rule on intervals of 1/2, which the pieces' breaks (half-integers, integers)
  // never split, integrates the cubics exactly: round-off only.
  using K = TypeParam;
  const int n = 7;
  const mpm::GridGeometry<1> g = grid(n, K::ghost);
  const std::array<Real, 2> expected =
      K::width == 3 ? std::array<Real, 2>{13.0 / 24, 23.0 / 24} : std::array<Real, 2>{7.0 / 12, 11.0 / 12};
  for (int node = 0; node <= n; ++node) {
    Real integral = 0;
    for (int k = 0; k < 2 * n; ++k) {
      const Real a = 0.5 * k, b = a + 0.5, m = 0.5 * (a + b);
      // Evaluate each interval's ends from inside it, so that a break at an end takes this piece's value.
      const Real fa = node_weight<K>(g, k == 0 ? a : a + 1e-300 + a * kEps, node)[0];
      const Real fb = node_weight<K>(g, k == 2 * n - 1 ? b : b - b * kEps, node)[0];
      integral += (b - a) / 6 * (fa + 4 * node_weight<K>(g, m, node)[0] + fb);
    }
    const int from_face = std::min(node, n - node);
    const Real want = from_face < 2 ? expected[from_face] : 1.0;
    EXPECT_NEAR(integral, want, 1e-13) << "node " << node;
  }
}

TYPED_TEST(ClampedKernel, UniformWeightsAwayFromTheFaces) {
  // Bit for bit: clamping changes nothing where the uniform stencil stays inside (half a cell from a face for
  // the quadratic spline, a cell for the cubic one). Both through the same (not inlined) function: GCC 12's
  // SLP vectoriser fuses a multiply and an add/subtract pair into one vfmaddsub despite -ffp-contract=off,
  // differently in different inlined contexts (1 ulp of dw, seen in this test), so identical code is compared
  // with itself.
  using K = TypeParam;
  const int n = 7;
  const Real reach = K::width == 3 ? 0.5 : 1.0;
  const mpm::GridGeometry<1> clamped = grid(n, K::ghost), open = grid(n, K::ghost, false);
  std::mt19937_64 rng(20);
  std::uniform_real_distribution<Real> inside(reach, n - reach);
  for (int k = 0; k < 2000; ++k) {
    const Real xi = inside(rng);
    const Located<K> s = locate<K>(clamped, xi), uniform = locate<K>(open, xi);
    EXPECT_EQ(s.base, uniform.base) << xi;
    for (int j = 0; j < K::width; ++j) {
      EXPECT_EQ(s.w[j], uniform.w[j]) << xi;
      EXPECT_EQ(s.dw[j], uniform.dw[j]) << xi;
    }
  }
}

TYPED_TEST(ClampedKernel, LanesLocateAndWeighLikeOneParticle) {
  // build_stencils (locate_block in lanes) against make_stencil, and weights_at in lanes against one
  // particle, bit for bit, on a clamped 2-D grid with particles near every face and corner.
  using K = TypeParam;
  mpm::GridGeometry<2> g{mpm::Vec<2>(-0.3, 0.1), 0.25, {5, 4}, K::ghost};
  g.clamped = {true, true, true, true};
  mpm::ParticleSet<2> p;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> unit(0.0, 1.0);
  const mpm::Vec<2> hi = g.hi();
  for (int k = 0; k < 3 * mpm::LaneBlock::width + 3; ++k) {
    mpm::Vec<2> x;
    for (int d = 0; d < 2; ++d) x[d] = g.lo[d] + unit(rng) * (hi[d] - g.lo[d]);
    if (k < 4) x = mpm::Vec<2>(k % 2 ? hi[0] : g.lo[0], k / 2 ? hi[1] : g.lo[1]);  // the corners themselves
    p.add(x, mpm::Vec<2>::Zero(), 1.0, 1.0, mpm::Vec<2>::Constant(0.05), 0);
  }
  // The records build_stencils keeps, and the axis data ParticleStencils locates again in lanes where the
  // transfers read them.
  std::vector<mpm::StoredStencil<2, K>> stencils;
  mpm::build_stencils<2, K>(p, g, stencils);
  const mpm::NodeLayout<2> nl(g);
  const mpm::ParticleStencils<2, K> located{stencils, p};
  for (std::ptrdiff_t b = 0; b < mpm::LaneBlock::count(p.size()); ++b) {
    const mpm::LaneBlock block(b, static_cast<std::ptrdiff_t>(p.size()));
    const mpm::StencilLanes<2, K> lanes = located.lanes(block, g, nl.inv_h);
    for (int k = 0; k < block.active; ++k) {
      const std::size_t i = static_cast<std::size_t>(block.first + k);
      const auto one = mpm::make_stencil<2, K>(g, nl, p.x[i], p.half_length(i));
      EXPECT_EQ(one.node, stencils[i].node) << i;
      EXPECT_EQ(one.tile_slot, stencils[i].tile_slot) << i;
      EXPECT_EQ(one.node, lanes.node[k]) << i;
      EXPECT_EQ(one.tile_slot, lanes.tile_slot[k]) << i;
      for (int d = 0; d < 2; ++d) {
        mpm::RealLanes w[K::width], dw[K::width];
        K::weights_at(lanes.axis[d], w, dw);
        Real w1[K::width], dw1[K::width];
        K::weights_at(one.axis[d], w1, dw1);
        for (int j = 0; j < K::width; ++j) {
          EXPECT_EQ(w[j][k], w1[j]) << i;
          EXPECT_EQ(dw[j][k], dw1[j]) << i;
        }
      }
    }
  }
}

template <int Dim, class Kernel>
void expect_corners_reproduce_linear_fields() {
  // Every corner, edge and face point of a clamped box (h = 0.1, offset origin) and random points inside: the
  // tensor product visits only nodes of the box, sums to 1 and reproduces x (round-off of width^Dim terms).
  mpm::GridGeometry<Dim> g;
  for (int d = 0; d < Dim; ++d) g.lo[d] = 0.2 - 0.3 * d;
  g.h = 0.1;
  g.cells.fill(Kernel::width - 1);
  g.ghost = Kernel::ghost;
  g.clamped.fill(true);
  const mpm::NodeLayout<Dim> nl(g);
  std::mt19937_64 rng(11 + Dim);
  std::uniform_int_distribution<int> where(0, 2);
  std::uniform_real_distribution<Real> unit(0.0, 1.0);
  for (int sample = 0; sample < 300; ++sample) {
    mpm::Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) {
      const int c = where(rng);  // lower face, upper face or inside
      const Real length = g.h * g.cells[d];
      x[d] = g.lo[d] + (c == 0 ? 0 : c == 1 ? length : unit(rng) * length);
    }
    Real sum_w = 0;
    mpm::Vec<Dim> sum_wx = mpm::Vec<Dim>::Zero();
    mpm::Mat<Dim> sum_x_dw = mpm::Mat<Dim>::Zero();
    mpm::for_each_node(mpm::make_stencil<Dim, Kernel>(g, nl, x, mpm::Vec<Dim>::Zero()), nl,
                       [&](std::int32_t node, Real w, const mpm::Vec<Dim>& dw) {
                         const mpm::IVec<Dim> i = g.coords(node);
                         for (int d = 0; d < Dim; ++d) {
                           EXPECT_GE(i[d], 0);
                           EXPECT_LE(i[d], g.cells[d]);
                         }
                         const mpm::Vec<Dim> xn = g.position(i);
                         sum_w += w;
                         sum_wx += w * xn;
                         sum_x_dw += xn * dw.transpose();
                       });
    EXPECT_NEAR(sum_w, 1.0, kSumTol);
    for (int a = 0; a < Dim; ++a) {
      EXPECT_NEAR(sum_wx[a], x[a], 1e-14);
      for (int b = 0; b < Dim; ++b) EXPECT_NEAR(sum_x_dw(a, b), a == b ? 1.0 : 0.0, 1e-13 / g.h);
    }
  }
}

TYPED_TEST(ClampedKernel, TensorProductsReproduceLinearFieldsAtTheCorners) {
  expect_corners_reproduce_linear_fields<2, TypeParam>();
  expect_corners_reproduce_linear_fields<3, TypeParam>();
}

}  // namespace

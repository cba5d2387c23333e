// CPDI weights (Sadeghirad, Brannon & Burghardt 2011; shape/cpdi.hpp): the partition of unity and the linear
// reproduction for sheared and rotated domains, the hat inside one cell, the corners' trapezoid rule on a
// node, the domain bound of one cell, the axis-aligned box kernel, and lanes bit for bit equal to one
// particle. CPDI2's (Sadeghirad, Brannon & Guilkey 2013; shape/cpdi2.hpp) for general quadrilaterals and
// hexahedra: the same properties, and CPDI's weights for parallelograms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/lanes.hpp"

namespace {
using mpm::Real;
template <int Dim>
using Vec = mpm::Vec<Dim>;
template <int Dim>
using Mat = mpm::Mat<Dim>;

/// A grid of h = 0.1 with an offset origin, 12 cells per axis, CPDI's ghost layers.
template <int Dim>
mpm::GridGeometry<Dim> grid() {
  mpm::GridGeometry<Dim> g;
  for (int d = 0; d < Dim; ++d) g.lo[d] = 0.2 - 0.3 * d;
  g.h = 0.1;
  g.cells.fill(12);
  g.ghost = mpm::CpdiKernel<Dim>::ghost;
  return g;
}

/// The sums of one particle's weights over its nodes: sum S, sum S x_i, sum grad S, sum (x_i - x_p) (x) grad
/// S (I when sum grad S = 0: the linear reproduction of gradients, with terms of the size of one); and the
/// weights by node.
template <int Dim>
struct Sums {
  Real S = 0, min_S = 1;
  Vec<Dim> Sx = Vec<Dim>::Zero(), dS = Vec<Dim>::Zero();
  Mat<Dim> xdS = Mat<Dim>::Zero();
  std::vector<std::pair<std::int32_t, Real>> weights;
  std::vector<Vec<Dim>> gradients;
};

template <int Dim, class K = mpm::CpdiKernel<Dim>>
Sums<Dim> sums(const mpm::GridGeometry<Dim>& g, const Vec<Dim>& x, const mpm::Domain<Dim, K>& domain) {
  const mpm::NodeLayout<Dim> nl(g);
  Sums<Dim> s;
  mpm::for_each_node(mpm::make_stencil<Dim, K>(g, nl, x, domain), nl,
                     [&](std::int32_t n, Real S, const Vec<Dim>& dS) {
                       const Vec<Dim> xi = g.position(g.coords(n));
                       s.S += S;
                       s.min_S = std::min(s.min_S, S);
                       s.Sx += S * xi;
                       s.dS += dS;
                       s.xdS += (xi - x) * dS.transpose();
                       s.weights.emplace_back(n, S);
                       s.gradients.push_back(dS);
                     });
  return s;
}

/// A random deformation gradient with det F in [0.3, 3] and entries up to `size` off the identity.
template <int Dim>
Mat<Dim> random_F(std::mt19937_64& rng, Real size) {
  std::uniform_real_distribution<Real> u(-size, size);
  for (;;) {
    Mat<Dim> F = Mat<Dim>::Identity();
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) F(a, b) += u(rng);
    const Real J = F.determinant();
    if (J > 0.3 && J < 3) return F;
  }
}

template <int Dim>
void expect_partition_of_unity_and_linear_reproduction(Real size) {
  // Sheared, stretched and rotated domains of 1 and 2 particles per cell (l_0 = h/2, h/4), some beyond the
  // bound of one cell (scaled). Sums of at most 4^Dim 2^Dim terms; measured worst over both sizes, 3-D: |sum
  // S - 1| 4.4e-16, |sum S x_i - x_p| 7.0e-16, h |sum grad S| 1.9e-14, |sum (x_i - x_p) (x) grad S -
  // I| 6.4e-14 (the gradients of the smallest scaled domains are the largest terms).
  const mpm::GridGeometry<Dim> g = grid<Dim>();
  std::mt19937_64 rng(17 + Dim);
  std::uniform_real_distribution<Real> where(0.4, 0.8);
  for (int sample = 0; sample < 400; ++sample) {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = g.lo[d] + where(rng) * g.h * g.cells[d];
    const Real l0 = sample % 2 ? g.h / 2 : g.h / 4;
    const Mat<Dim> R = random_F<Dim>(rng, size) * l0;
    const Sums<Dim> s = sums<Dim>(g, x, R);
    EXPECT_NEAR(s.S, 1, 1e-14) << sample;
    EXPECT_GE(s.min_S, 0) << sample;
    EXPECT_LT((s.Sx - x).norm(), 1e-14) << sample;
    EXPECT_LT(s.dS.norm() * g.h, 1e-13) << sample;
    EXPECT_LT((s.xdS - Mat<Dim>::Identity()).norm(), 1e-13) << sample;
  }
}

TEST(CpdiWeights, PartitionOfUnityAndLinearReproductionForDistortedDomains2D) {
  expect_partition_of_unity_and_linear_reproduction<2>(0.8);
  expect_partition_of_unity_and_linear_reproduction<2>(3.0);  // most reach beyond one cell and are scaled
}

TEST(CpdiWeights, PartitionOfUnityAndLinearReproductionForDistortedDomains3D) {
  expect_partition_of_unity_and_linear_reproduction<3>(0.8);
  expect_partition_of_unity_and_linear_reproduction<3>(3.0);
}

TEST(CpdiWeights, AnAxisAlignedDomainInsideOneCellGivesTheHat) {
  // Every corner in the cell of x_p: the hats are linear there, so their corner average is N_i(x_p), and the
  // averaged gradient is the hat's.
  const mpm::GridGeometry<2> g = grid<2>();
  const Vec<2> x(g.lo[0] + 3.37 * g.h, g.lo[1] + 5.61 * g.h);
  const Mat<2> R = Vec<2>(0.2 * g.h, 0.1 * g.h).asDiagonal();
  const Sums<2> s = sums<2>(g, x, R);
  const Real r0 = 0.37, r1 = 0.61;
  for (std::size_t k = 0; k < s.weights.size(); ++k) {
    const mpm::IVec<2> c = g.coords(s.weights[k].first);
    const int i = c[0] - 3, j = c[1] - 5;  // node (i, j) of the cell, or outside it
    const Real wx = i == 0 ? 1 - r0 : i == 1 ? r0 : 0, wy = j == 0 ? 1 - r1 : j == 1 ? r1 : 0;
    const Real gx = i == 0 ? -1 : i == 1 ? 1 : 0, gy = j == 0 ? -1 : j == 1 ? 1 : 0;
    EXPECT_NEAR(s.weights[k].second, wx * wy, 1e-15) << i << " " << j;
    EXPECT_NEAR(s.gradients[k][0] * g.h, gx * wy, 1e-14) << i << " " << j;
    EXPECT_NEAR(s.gradients[k][1] * g.h, wx * gy, 1e-14) << i << " " << j;
  }
}

TEST(CpdiWeights, ANodeCentredDomainAveragesTheHatAtItsCorners) {
  // x_p on a node, half-lengths l = 0.3 h: along each axis the node's factor is (N(-l) + N(l)) / 2 = 1 - l
  // and each neighbour's l / 2 (GIMP integrates the hat exactly instead: 1 - l/2 and l/4).
  const mpm::GridGeometry<2> g = grid<2>();
  const Vec<2> x(g.lo[0] + 6 * g.h, g.lo[1] + 4 * g.h);
  const Sums<2> s = sums<2>(g, x, Mat<2>::Identity() * (0.3 * g.h));
  for (const auto& [n, S] : s.weights) {
    const mpm::IVec<2> c = g.coords(n);
    const int i = c[0] - 6, j = c[1] - 4;
    const auto factor = [](int k) { return k == 0 ? 0.7 : std::abs(k) == 1 ? 0.15 : 0.0; };
    EXPECT_NEAR(S, factor(i) * factor(j), 1e-15) << i << " " << j;
  }
}

TEST(CpdiWeights, AQuarterTurnOfASquareDomainGivesTheSameWeights) {
  // F = the rotation by pi/2 maps the square onto itself (its corners permuted), so the weights and gradients
  // are those of F = I; cpGIMP's half-lengths l_0 F_dd would be 0 there.
  const mpm::GridGeometry<3> g = grid<3>();
  const Vec<3> x(g.lo[0] + 5.3 * g.h, g.lo[1] + 6.8 * g.h, g.lo[2] + 4.45 * g.h);
  Mat<3> Q;
  Q << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Sums<3> still = sums<3>(g, x, Mat<3>::Identity() * (g.h / 4)), turned = sums<3>(g, x, Q * (g.h / 4));
  ASSERT_EQ(still.weights.size(), turned.weights.size());
  for (std::size_t k = 0; k < still.weights.size(); ++k) {
    EXPECT_NEAR(turned.weights[k].second, still.weights[k].second, 1e-15);
    EXPECT_LT((turned.gradients[k] - still.gradients[k]).norm() * g.h, 1e-14);
  }
}

TEST(CpdiWeights, ADomainBeyondOneCellIsScaledAboutItsCentre) {
  // r_1 = (0.6 h, 0), r_2 = (0.9 h, 0.25 h): the corners reach 1.5 cells along x, so R is scaled by 2/3: the
  // weights are those of the domain R / 1.5, and no node beyond one cell of a corner of it is reached.
  const mpm::GridGeometry<2> g = grid<2>();
  const Vec<2> x(g.lo[0] + 6.2 * g.h, g.lo[1] + 5.5 * g.h);
  Mat<2> R;
  R << 0.6 * g.h, 0.9 * g.h, 0, 0.25 * g.h;
  const Sums<2> wide = sums<2>(g, x, R), scaled = sums<2>(g, x, R / 1.5);
  ASSERT_EQ(wide.weights.size(), scaled.weights.size());
  for (std::size_t k = 0; k < wide.weights.size(); ++k) {
    EXPECT_NEAR(wide.weights[k].second, scaled.weights[k].second, 1e-15);
    EXPECT_LT((wide.gradients[k] - scaled.gradients[k]).norm() * g.h, 1e-14);
  }
  EXPECT_NEAR(wide.S, 1, 1e-15);
  EXPECT_LT((wide.xdS - Mat<2>::Identity()).norm(), 1e-14);
}

TEST(CpdiWeights, TheBoxKernelReproducesLinearFieldsForEveryHalfLength) {
  // CpdiKernel::Box (rigid-body points, the decomposition): (N(xi - l) + N(xi + l)) / 2 along one axis, for l
  // in (0, 1] cells, and its gradient (N(xi + l) - N(xi - l)) / (2 l).
  using Box = mpm::CpdiKernel<2>::Box;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> u(0.0, 1.0);
  for (int sample = 0; sample < 2000; ++sample) {
    const Real xi = 3 + 5 * u(rng), l = sample == 0 ? 1.0 : 1e-3 + (1 - 1e-3) * u(rng);
    Box::Axis a;
    const int base = Box::locate(xi, l, a);
    Real w[Box::width], dw[Box::width], sum = 0, first = 0, slope = 0, dsum = 0;
    Box::weights_at(a, w, dw);
    for (int k = 0; k < Box::width; ++k) {
      const Real lo = std::max(0.0, 1 - std::abs(xi - l - (base + k))),
                 hi = std::max(0.0, 1 - std::abs(xi + l - (base + k)));
      EXPECT_NEAR(w[k], (lo + hi) / 2, 1e-15);
      sum += w[k];
      first += (base + k) * w[k];
      dsum += dw[k];
      slope += (base + k) * dw[k];
    }
    EXPECT_NEAR(sum, 1, 1e-15);
    EXPECT_NEAR(first, xi, 1e-14);
    EXPECT_NEAR(dsum, 0, 1e-12);
    EXPECT_NEAR(slope, 1, 1e-12);
  }
}

/// The corners x + R s_c of a CPDI domain (Corners, column c corner c) moved by up to `size` each: a general
/// quadrilateral or hexahedron.
template <int Dim>
mpm::Corners<Dim> distorted_corners(std::mt19937_64& rng, const Vec<Dim>& x, const Mat<Dim>& R, Real size) {
  std::uniform_real_distribution<Real> u(-size, size);
  mpm::Corners<Dim> corners;
  for (int c = 0; c < (1 << Dim); ++c) {
    Vec<Dim> s;
    for (int k = 0; k < Dim; ++k) s[k] = mpm::CpdiKernel<Dim>::sign(c, k);
    corners.col(c) = x + R * s;
    for (int d = 0; d < Dim; ++d) corners(d, c) += u(rng);
  }
  return corners;
}

template <int Dim>
void expect_cpdi2_partition_of_unity_and_linear_reproduction(Real size) {
  // Random quadrilaterals and hexahedra: CPDI's domains of 1 and 2 particles per cell with their corners
  // moved by up to 0.3 l_0 each, the particle at their centroid; some reach beyond one cell (scaled).
  // Measured worst over both sizes, 3-D: |sum S - 1| 6.7e-16, |sum S x_i - x_p| 4.4e-16, h |sum grad
  // S| 1.1e-14, |sum (x_i - x_p) (x) grad S - I| 3.1e-14; the bounds are CPDI's.
  using K = mpm::Cpdi2Kernel<Dim>;
  const mpm::GridGeometry<Dim> g = grid<Dim>();
  std::mt19937_64 rng(31 + Dim);
  std::uniform_real_distribution<Real> where(0.4, 0.8);
  int unfolded = 0;
  for (int sample = 0; sample < 400; ++sample) {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = g.lo[d] + where(rng) * g.h * g.cells[d];
    const Real l0 = sample % 2 ? g.h / 2 : g.h / 4;
    const mpm::Corners<Dim> corners = distorted_corners<Dim>(rng, x, random_F<Dim>(rng, size) * l0, 0.3 * l0);
    Real xc[1 << Dim][Dim], near[Dim], centroid[Dim];
    for (int c = 0; c < (1 << Dim); ++c)
      for (int d = 0; d < Dim; ++d) xc[c][d] = corners(d, c);
    for (int d = 0; d < Dim; ++d) near[d] = x[d];
    if (!mpm::corner_centroid<Dim>(xc, near, centroid)) continue;  // folded by the moves: a run stops there
    ++unfolded;
    const Vec<Dim> x_p = Eigen::Map<const Vec<Dim>>(centroid);
    const Sums<Dim> s = sums<Dim, K>(g, x_p, corners);
    EXPECT_NEAR(s.S, 1, 1e-14) << sample;
    EXPECT_LT((s.Sx - x_p).norm(), 1e-14) << sample;
    EXPECT_LT(s.dS.norm() * g.h, 1e-13) << sample;
    EXPECT_LT((s.xdS - Mat<Dim>::Identity()).norm(), 1e-13) << sample;
  }
  EXPECT_GT(unfolded, 200);  // measured: 399 and 388 (2-D), 374 and 235 (3-D) of 400 kept
}

TEST(Cpdi2Weights, PartitionOfUnityAndLinearReproductionForQuadrilaterals) {
  expect_cpdi2_partition_of_unity_and_linear_reproduction<2>(0.8);
  expect_cpdi2_partition_of_unity_and_linear_reproduction<2>(3.0);
}

TEST(Cpdi2Weights, PartitionOfUnityAndLinearReproductionForHexahedra) {
  expect_cpdi2_partition_of_unity_and_linear_reproduction<3>(0.8);
  expect_cpdi2_partition_of_unity_and_linear_reproduction<3>(3.0);
}

template <int Dim>
void expect_parallelograms_weighed_as_cpdi() {
  // The corners x_p + R s_c of CPDI's domain give CPDI's weights and gradients, node by node, scaled ones
  // too: the two compute them by different routes (2^-D R^-T against Gauss points with cofactors), so to
  // round-off, which for the gradients grows with the condition of R (det F down to 0.3 with entries up to
  // 4): measured worst |difference| / (1/h + |gradient|) 1.1e-14 in 2-D, 3.2e-14 in 3-D.
  const mpm::GridGeometry<Dim> g = grid<Dim>();
  std::mt19937_64 rng(7 + Dim);
  std::uniform_real_distribution<Real> where(0.4, 0.8);
  Real worst = 0;  // |difference of the gradients| / (1/h + |gradient|)
  for (int sample = 0; sample < 100; ++sample) {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = g.lo[d] + where(rng) * g.h * g.cells[d];
    const Mat<Dim> R = random_F<Dim>(rng, sample % 2 ? 0.8 : 3.0) * (g.h / 4);
    const Sums<Dim> cpdi = sums<Dim>(g, x, R);
    const Sums<Dim> cpdi2 = sums<Dim, mpm::Cpdi2Kernel<Dim>>(g, x, distorted_corners<Dim>(rng, x, R, 0.0));
    ASSERT_EQ(cpdi.weights.size(), cpdi2.weights.size());
    for (std::size_t k = 0; k < cpdi.weights.size(); ++k) {
      EXPECT_EQ(cpdi.weights[k].first, cpdi2.weights[k].first);
      EXPECT_NEAR(cpdi.weights[k].second, cpdi2.weights[k].second, 1e-15) << sample;
      worst = std::max(
          worst, (cpdi.gradients[k] - cpdi2.gradients[k]).norm() / (1 / g.h + cpdi.gradients[k].norm()));
    }
  }
  EXPECT_LT(worst, 1e-13);
}

TEST(Cpdi2Weights, ParallelogramsWeighAsCpdi2D) {
  expect_parallelograms_weighed_as_cpdi<2>();
}
TEST(Cpdi2Weights, ParallelepipedsWeighAsCpdi3D) {
  expect_parallelograms_weighed_as_cpdi<3>();
}

template <int Dim, class K = mpm::CpdiKernel<Dim>>
void expect_lanes_like_one_particle() {
  // build_stencils (locate_block in lanes) against make_stencil, and for_each_node in lanes against one
  // particle, bit for bit, for distorted domains (CPDI2's corners moved off the parallelograms).
  const mpm::GridGeometry<Dim> g = grid<Dim>();
  mpm::ParticleSet<Dim> p;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<Real> where(0.1, 0.9);
  for (int k = 0; k < 3 * mpm::LaneBlock::width + 3; ++k) {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = g.lo[d] + where(rng) * g.h * g.cells[d];
    p.add(x, Vec<Dim>::Zero(), 1.0, 1.0, Vec<Dim>::Constant(g.h / 4), 0);
    p.F.back() = random_F<Dim>(rng, 2.0);
  }
  if constexpr (mpm::moves_corners<K>) {
    mpm::place_corners(p);
    for (std::size_t i = 0; i < p.size(); ++i)
      p.corners[i] =
          distorted_corners<Dim>(rng, Vec<Dim>::Zero(), Mat<Dim>::Zero(), 0.05 * g.h) + p.corners[i];
  }
  std::vector<mpm::Stencil<Dim, K>> stencils;
  mpm::build_stencils<Dim, K>(p, g, stencils);
  const mpm::NodeLayout<Dim> nl(g);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto one = mpm::make_stencil<Dim, K>(g, nl, p.x[i], mpm::domain_of<Dim, K>(p, i));
    EXPECT_EQ(one.node, stencils[i].node) << i;
    EXPECT_EQ(one.tile_slot, stencils[i].tile_slot) << i;
    EXPECT_EQ(std::memcmp(one.axis.data(), stencils[i].axis.data(), sizeof(one.axis)), 0) << i;
  }
  for (std::ptrdiff_t b = 0; b < mpm::LaneBlock::count(p.size()); ++b) {
    const mpm::LaneBlock block(b, static_cast<std::ptrdiff_t>(p.size()));
    const mpm::LaneStencil<Dim, K> lanes(mpm::ParticleStencils<Dim, K>{stencils, p}, block, g, nl.inv_h);
    std::vector<Real> S;
    std::vector<Vec<Dim>> dS;
    mpm::for_each_node(lanes, nl, [&](std::int32_t, const mpm::RealLanes& w, const mpm::RealLanes(&dw)[Dim]) {
      for (int k = 0; k < block.active; ++k) {
        S.push_back(w[k]);
        Vec<Dim> grad;
        for (int d = 0; d < Dim; ++d) grad[d] = dw[d][k];
        dS.push_back(grad);
      }
    });
    std::size_t node = 0;
    const int active = block.active;
    std::vector<std::vector<std::pair<Real, Vec<Dim>>>> one(active);
    for (int k = 0; k < active; ++k)
      mpm::for_each_node(stencils[block.first + k], nl,
                         [&](std::int32_t, Real w, const Vec<Dim>& dw) { one[k].emplace_back(w, dw); });
    for (std::size_t n = 0; n < one[0].size(); ++n)
      for (int k = 0; k < active; ++k, ++node) {
        EXPECT_EQ(S[node], one[k][n].first);
        for (int d = 0; d < Dim; ++d) EXPECT_EQ(dS[node][d], one[k][n].second[d]);
      }
  }
}

TEST(CpdiWeights, LanesLocateAndWeighLikeOneParticle2D) {
  expect_lanes_like_one_particle<2>();
}
TEST(CpdiWeights, LanesLocateAndWeighLikeOneParticle3D) {
  expect_lanes_like_one_particle<3>();
}
TEST(Cpdi2Weights, LanesLocateAndWeighLikeOneParticle2D) {
  expect_lanes_like_one_particle<2, mpm::Cpdi2Kernel<2>>();
}
TEST(Cpdi2Weights, LanesLocateAndWeighLikeOneParticle3D) {
  expect_lanes_like_one_particle<3, mpm::Cpdi2Kernel<3>>();
}

}  // namespace

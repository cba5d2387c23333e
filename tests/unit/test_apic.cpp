// APIC's transfers (Jiang et al. 2015; transfer/p2g.hpp's AffineMomentum, g2p.hpp's g2p_affine,
// lanes.hpp's LaneStencil::locate_nodes) through the real stencils and scatter order, for every kernel in 2-D
// and 3-D:
//   * an affine velocity field v = a + C x with B_p = C D_p makes the round trip P2G-G2P without loss: every
//   node
//     with mass gets a + C x_i, every particle gets back a + C x_p and C D_p (D_p = sum_i S_ip (x_i - x_p)
//     (x_i - x_p)^T, summed here from the one-particle stencils, independently of the lanes);
//   * with B_p = 0, P2G gives Momentum's bits;
//   * P2G and G2P each keep the angular momentum sum_p m_p (x_p x v_p + eps : B_p^T) = sum_i x_i x m_i v_i of
//   any
//     particle velocities and matrices.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kernel_cases.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/p2g.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace {

using mpm::Mat;
using mpm::Real;
using mpm::Vec;

using Cases = mpm::testing::KernelCases2D3D;
using CaseName = mpm::testing::KernelCaseName;
template <class C>
class Apic : public ::testing::Test {};
TYPED_TEST_SUITE(Apic, Cases, CaseName);

/// A grid of 8 cells per axis (h = 0.1, offset origin) and 200 particles at random places in it, with random
/// masses, velocities and half-lengths h/4 (2 particles per cell).
template <int Dim, class Kernel>
struct Setup {
  mpm::GridGeometry<Dim> geo;
  mpm::ParticleSet<Dim> p;
  std::vector<mpm::StoredStencil<Dim, Kernel>> stored;
  mpm::ScatterOrder<Dim> order;
  std::mt19937_64 rng{77 + Dim};

  Setup() : geo(geometry()), order(geo, Kernel::width) {
    std::uniform_real_distribution<Real> unit(0.0, 1.0), sym(-1.0, 1.0);
    for (int i = 0; i < 200; ++i) {
      Vec<Dim> x, v;
      for (int d = 0; d < Dim; ++d) x[d] = geo.lo[d] + unit(rng) * geo.h * geo.cells[d], v[d] = sym(rng);
      p.add(x, v, 1e-3 * (0.5 + unit(rng)), 1e-4, Vec<Dim>::Constant(0.25 * geo.h), 0);
    }
    p.B.assign(p.size(), Mat<Dim>::Zero());
    mpm::place_corners(p);  // CPDI2's domains
    mpm::build_stencils<Dim, Kernel>(p, geo, stored);
    order.build(mpm::StencilTiles<Dim, Kernel>{stored}, p.id);
  }
  mpm::ParticleStencils<Dim, Kernel> stencils() const { return {stored, p}; }
  static mpm::GridGeometry<Dim> geometry() {
    mpm::GridGeometry<Dim> g;
    for (int d = 0; d < Dim; ++d) g.lo[d] = -0.35 + 0.3 * d;
    g.h = 0.1;
    g.cells.fill(8);
    g.ghost = Kernel::ghost;
    return g;
  }
  /// D_p = sum_i S_ip (x_i - x_p)(x_i - x_p)^T from the one-particle stencil.
  Mat<Dim> inertia(std::size_t i) const {
    const mpm::NodeLayout<Dim> nl(geo);
    Mat<Dim> D = Mat<Dim>::Zero();
    mpm::for_each_node(stencils().at(i, geo, nl), nl, [&](std::int32_t n, Real S, const Vec<Dim>&) {
      const Vec<Dim> dx = geo.position(geo.coords(n)) - p.x[i];
      D += S * dx * dx.transpose();
    });
    return D;
  }
  mpm::Grid<Dim> p2g(bool affine) {
    mpm::Grid<Dim> grid(geo);
    mpm::p2g<mpm::Scatter{.mass_momentum = true, .force = false}>(
        p, stencils(), order, {}, grid, mpm::KeepNothing{}, 0, false, affine ? &p.B : nullptr);
    return grid;
  }
};

/// The angular momentum about the origin of a point mass m at x moving at v, with the spin eps : B^T of an
/// affine matrix B (Jiang et al. 2015): the z component in 2-D (one entry), the vector in 3-D.
template <int Dim>
std::array<Real, 3> angular_momentum(Real m, const Vec<Dim>& x, const Vec<Dim>& v, const Mat<Dim>& B) {
  if constexpr (Dim == 2)
    return {m * (x[0] * v[1] - x[1] * v[0] + B(1, 0) - B(0, 1)), 0, 0};
  else
    return {m * (x[1] * v[2] - x[2] * v[1] + B(2, 1) - B(1, 2)),
            m * (x[2] * v[0] - x[0] * v[2] + B(0, 2) - B(2, 0)),
            m * (x[0] * v[1] - x[1] * v[0] + B(1, 0) - B(0, 1))};
}

TYPED_TEST(Apic, AffineFieldMakesTheRoundTripWithoutLoss) {
  // Round-off: sums of width^Dim terms of velocities <= 2 (|a| + |C| |x| with |x| < 1.2): 1e-13 absolute.
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  Setup<Dim, Kernel> s;
  std::uniform_real_distribution<Real> sym(-1.0, 1.0);
  Vec<Dim> a;
  Mat<Dim> C;
  for (int r = 0; r < Dim; ++r) {
    a[r] = sym(s.rng);
    for (int c = 0; c < Dim; ++c) C(r, c) = sym(s.rng);
  }
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    s.p.v[i] = a + C * s.p.x[i];
    s.p.B[i] = C * s.inertia(i);
  }
  mpm::Grid<Dim> grid = s.p2g(true);
  mpm::grid_velocity(grid, 0.0);
  int loaded = 0;
  for (std::size_t n = 0; n < grid.size(); ++n) {
    if (!(grid.nodes[n].m > 0)) continue;
    ++loaded;
    const Vec<Dim> want = a + C * s.geo.position(s.geo.coords(static_cast<std::ptrdiff_t>(n)));
    for (int d = 0; d < Dim; ++d) EXPECT_NEAR(grid.nodes[n].v[d], want[d], 1e-13) << "node " << n;
  }
  EXPECT_GT(loaded, 0);
  std::vector<Vec<Dim>> v;
  std::vector<Mat<Dim>> B;
  mpm::g2p_affine(s.stencils(), grid, &mpm::GridNode<Dim>::v, v, B);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const Vec<Dim> want_v = a + C * s.p.x[i];
    const Mat<Dim> want_B = C * s.inertia(i);
    for (int r = 0; r < Dim; ++r) {
      EXPECT_NEAR(v[i][r], want_v[r], 1e-13) << i;
      for (int c = 0; c < Dim; ++c) EXPECT_NEAR(B[i](r, c), want_B(r, c), 1e-15) << i;  // entries ~h^2
    }
  }
}

TYPED_TEST(Apic, WithoutAffineMatricesP2GIsMomentumBitForBit) {
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  Setup<Dim, Kernel> s;
  const mpm::Grid<Dim> affine = s.p2g(true), plain = s.p2g(false);
  EXPECT_EQ(std::memcmp(affine.nodes.data(), plain.nodes.data(), affine.bytes()), 0);
}

TYPED_TEST(Apic, P2GAndG2PKeepTheAngularMomentum) {
  // Random velocities and matrices. Sums of a few hundred terms of size m |x| |v| ~ 1e-3: 1e-15 absolute.
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  Setup<Dim, Kernel> s;
  std::uniform_real_distribution<Real> sym(-1.0, 1.0);
  for (Mat<Dim>& B : s.p.B)
    for (int k = 0; k < Dim * Dim; ++k) B.data()[k] = 0.01 * sym(s.rng);  // h^2 times a gradient of order 1
  std::array<Real, 3> particles{}, nodes{};
  const auto add = [](std::array<Real, 3>& sum, const std::array<Real, 3>& L) {
    for (int k = 0; k < 3; ++k) sum[k] += L[k];
  };
  for (std::size_t i = 0; i < s.p.size(); ++i)
    add(particles, angular_momentum<Dim>(s.p.m[i], s.p.x[i], s.p.v[i], s.p.B[i]));
  mpm::Grid<Dim> grid = s.p2g(true);
  for (std::size_t n = 0; n < grid.size(); ++n)  // v holds the momentum m_i v_i until grid_velocity
    add(nodes, angular_momentum<Dim>(1.0, s.geo.position(s.geo.coords(static_cast<std::ptrdiff_t>(n))),
                                     grid.nodes[n].v, Mat<Dim>::Zero()));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(nodes[k], particles[k], 1e-15) << "P2G, component " << k;

  // G2P of any node velocities: the particles' angular momentum is sum_i m_i x_i x v_i with m_i their P2G
  // mass.
  std::array<Real, 3> grid_L{}, back{};
  for (std::size_t n = 0; n < grid.size(); ++n) {
    for (int d = 0; d < Dim; ++d) grid.nodes[n].v_new[d] = grid.nodes[n].m > 0 ? sym(s.rng) : 0.0;
    add(grid_L,
        angular_momentum<Dim>(grid.nodes[n].m, s.geo.position(s.geo.coords(static_cast<std::ptrdiff_t>(n))),
                              grid.nodes[n].v_new, Mat<Dim>::Zero()));
  }
  std::vector<Vec<Dim>> v;
  std::vector<Mat<Dim>> B;
  mpm::g2p_affine(s.stencils(), grid, &mpm::GridNode<Dim>::v_new, v, B);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    add(back, angular_momentum<Dim>(s.p.m[i], s.p.x[i], v[i], B[i]));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], grid_L[k], 1e-15) << "G2P, component " << k;
}

}  // namespace

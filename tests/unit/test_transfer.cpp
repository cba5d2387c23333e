// Particle-to-grid and grid-to-particle transfers (mpm/transfer/p2g.hpp, g2p.hpp) through the real stencils
// and scatter order, for every kernel in 1-D, 2-D and 3-D:
//   * P2G conserves mass and momentum: sum_i m_i = sum_p m_p and sum_i p_i = sum_p m_p v_p
//     (Wallstedt & Guilkey 2008, Eqs 8-9, by the partition of unity of the shape functions);
//   * G2P of a linear nodal velocity field v_i = v0 + L x_i gives every particle the displacement dt v(x_p)
//   and
//     the deformation gradient F = (I + dt L) F_old (Eqs 10-11 and 17, by linear reproduction).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "kernel_cases.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/g2p_stress.hpp"
#include "mpm/transfer/p2g.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace {

using mpm::Mat;
using mpm::Real;
using mpm::Vec;
constexpr Real kEps = std::numeric_limits<Real>::epsilon();
constexpr int kParticles = 300;

using Cases = mpm::testing::KernelCases1D2D3D;
using CaseName = mpm::testing::KernelCaseName;

template <class C>
class TransferTest : public ::testing::Test {};
TYPED_TEST_SUITE(TransferTest, Cases, CaseName);

// Particle half-lengths as fractions of h: GIMP is tested across (0, 1/2]; the other kernels ignore them.
template <class Kernel>
std::vector<Real> half_length_fractions() {
  if constexpr (std::is_same_v<Kernel, mpm::GimpKernel>)
    return {0.05, 0.125, 0.25, 0.4, 0.5};
  else
    return {0.5};
}

// An 8-cell-per-axis grid with an offset origin and a cell width that is not a power of two.
template <int Dim, class Kernel>
mpm::GridGeometry<Dim> test_geometry() {
  const std::array<Real, 3> origin = {-0.35, 0.2, 1.1};
  Vec<Dim> lo;
  for (int d = 0; d < Dim; ++d) lo[d] = origin[d];
  mpm::IVec<Dim> cells;
  cells.fill(8);
  return mpm::GridGeometry<Dim>{lo, 0.1, cells, Kernel::ghost};
}

// kParticles particles at pseudo-random positions at least `margin` inside the physical domain, with random
// masses, velocities in [-1, 1]^Dim and half-lengths `fraction * h` (fixed seed).
template <int Dim>
mpm::ParticleSet<Dim> random_particles(const mpm::GridGeometry<Dim>& g, Real margin, Real fraction,
                                       std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> unit(0.0, 1.0), sym(-1.0, 1.0), mass(0.5, 2.0);
  const Vec<Dim> hi = g.hi();
  mpm::ParticleSet<Dim> p;
  for (int i = 0; i < kParticles; ++i) {
    Vec<Dim> x, v;
    for (int d = 0; d < Dim; ++d) {
      x[d] = g.lo[d] + margin + unit(rng) * (hi[d] - g.lo[d] - 2 * margin);
      v[d] = sym(rng);
    }
    p.add(x, v, 1e-3 * mass(rng), 1e-4, Vec<Dim>::Constant(fraction * g.h), 0);
  }
  mpm::place_corners(p);  // the boxes' corners, the domains of CPDI2 (unused by the other kernels)
  return p;
}

// Stencils and scatter order of the particles, as the simulation builds them.
template <int Dim, class Kernel>
struct Transfer {
  const mpm::ParticleSet<Dim>& p;
  std::vector<mpm::StoredStencil<Dim, Kernel>> stored;
  mpm::ScatterOrder<Dim> order;

  Transfer(const mpm::ParticleSet<Dim>& particles, const mpm::GridGeometry<Dim>& g)
      : p(particles), order(g, Kernel::width) {
    mpm::build_stencils<Dim, Kernel>(p, g, stored);
    order.build(mpm::StencilTiles<Dim, Kernel>{stored}, p.id);
  }
  mpm::ParticleStencils<Dim, Kernel> stencils() const { return {stored, p}; }
};

TYPED_TEST(TransferTest, p2g_conserves_mass_and_momentum) {
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  const mpm::GridGeometry<Dim> geo = test_geometry<Dim, Kernel>();
  std::mt19937_64 rng(1000 + Dim);
  for (Real fraction : half_length_fractions<Kernel>()) {
    SCOPED_TRACE(::testing::Message() << "l_p/h = " << fraction);
    // Particles anywhere in the domain, boundaries included: their stencils reach the ghost layers.
    const mpm::ParticleSet<Dim> p = random_particles(geo, 0.0, fraction, rng);
    const Transfer<Dim, Kernel> t(p, geo);
    mpm::Grid<Dim> grid(geo);
    mpm::p2g<mpm::Scatter{.mass_momentum = true, .force = false}>(p, t.stencils(), t.order, {}, grid);

    // Reference sums in long double so that their own round-off is negligible.
    long double particle_mass = 0, grid_mass = 0;
    std::array<long double, Dim> particle_momentum{}, grid_momentum{}, momentum_scale{};
    for (std::size_t i = 0; i < p.size(); ++i) {
      particle_mass += p.m[i];
      for (int d = 0; d < Dim; ++d) {
        particle_momentum[d] += p.m[i] * p.v[i][d];
        momentum_scale[d] += std::abs(p.m[i] * p.v[i][d]);
      }
    }
    for (std::size_t n = 0; n < grid.size(); ++n) {
      grid_mass += grid.nodes[n].m;
      for (int d = 0; d < Dim; ++d) grid_momentum[d] += grid.nodes[n].v[d];  // momentum until grid_velocity
    }
    // Each nodal sum accumulates at most a few hundred contributions, each carrying the partition-of-unity
    // round-off of the stencil: relative error ~ tens of ulps, well below 1e-13.
    EXPECT_NEAR(static_cast<Real>(grid_mass), static_cast<Real>(particle_mass),
                1e-13 * static_cast<Real>(particle_mass));
    // Momentum components may cancel; the error scales with sum_p m_p |v_p|.
    for (int d = 0; d < Dim; ++d)
      EXPECT_NEAR(static_cast<Real>(grid_momentum[d]), static_cast<Real>(particle_momentum[d]),
                  1e-13 * static_cast<Real>(momentum_scale[d]))
          << "axis " << d;
  }
}

// The sum a P2G pass leaves in each node is fixed by the grid's tiles and the particle ids alone, not by how
// the particles are divided between threads or ranks: it equals the sum of the tiles' separate P2G sums added
// in colour order, f_i = ((P_i^0 + P_i^1) + ...) (mpm/transfer/scatter_order.hpp), to the last bit. Each
// P_i^c is computed here by a P2G pass over only the particles of colour-c tiles (whose footprints do not
// overlap), as a rank owning those tiles would; their colour-ordered sum must give the bits of the pass over
// all particles.
TYPED_TEST(TransferTest, p2g_equals_the_colour_ordered_sum_of_separate_tile_sums) {
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  mpm::GridGeometry<Dim> geo = test_geometry<Dim, Kernel>();
  geo.cells.fill(Dim == 3 ? 14 : 30);  // 2 to 5 tiles per axis: nodes where 2^Dim colours meet
  std::mt19937_64 rng(3000 + Dim);
  std::uniform_real_distribution<Real> sym(-1.0, 1.0);
  mpm::ParticleSet<Dim> p = random_particles(geo, 0.0, half_length_fractions<Kernel>().back(), rng);
  for (auto& s : p.sigma)
    for (Real& c : s.c) c = 1e3 * sym(rng);
  const Transfer<Dim, Kernel> all(p, geo);
  mpm::Grid<Dim> full(geo);
  mpm::p2g<mpm::Scatter{.mass_momentum = true, .force = true}>(p, all.stencils(), all.order, {}, full);

  mpm::Grid<Dim> sum(geo);
  int colours_met = 0;
  for (int colour = 0; colour < (1 << Dim); ++colour) {
    mpm::ParticleSet<Dim> q;  // the particles of the colour's tiles, in id order
    for (std::size_t i = 0; i < p.size(); ++i) {
      std::int32_t t = mpm::StencilTiles<Dim, Kernel>{all.stored}[i];
      int c = 0;
      for (int d = 0; d < Dim; ++d) {
        c |= (t % geo.tiles_along(d) & 1) << d;
        t /= geo.tiles_along(d);
      }
      if (c != colour) continue;
      q.add(p.x[i], p.v[i], p.m[i], p.V0[i], p.l0[i], 0);
      q.sigma.back() = p.sigma[i];
      q.corners.push_back(p.corners[i]);
    }
    if (q.size() == 0) continue;
    ++colours_met;
    const Transfer<Dim, Kernel> part(q, geo);
    mpm::Grid<Dim> tiles(geo);
    mpm::p2g<mpm::Scatter{.mass_momentum = true, .force = true}>(q, part.stencils(), part.order, {}, tiles);
    for (std::size_t n = 0; n < sum.size(); ++n) {
      sum.nodes[n].m += tiles.nodes[n].m;
      sum.nodes[n].v += tiles.nodes[n].v;
      sum.nodes[n].a += tiles.nodes[n].a;
    }
  }
  EXPECT_EQ(colours_met, 1 << Dim);
  std::size_t differ = 0;
  for (std::size_t n = 0; n < sum.size(); ++n)
    differ += sum.nodes[n].m != full.nodes[n].m || sum.nodes[n].v != full.nodes[n].v ||
              sum.nodes[n].a != full.nodes[n].a;
  EXPECT_EQ(differ, 0u) << "of " << sum.size() << " nodes";
}

// A stencil packs its tile's index in 22 bits (GridGeometry::max_tiles): a grid with more tiles is refused
// with one line before anything is sized (its geometry alone is built here; 1,300^3 cells are 163^3 tiles).
TEST(ScatterOrderLimits, AGridWithMoreTilesThanAStencilCanIndexIsRefused) {
  mpm::GridGeometry<3> huge{Vec<3>::Zero(), 1.0, {1300, 1300, 1300}, 1};
  ASSERT_GT(huge.tile_count(), mpm::GridGeometry<3>::max_tiles);
  try {
    mpm::ScatterOrder<3> order(huge, 2);
    ADD_FAILURE() << "accepted " << huge.tile_count() << " tiles";
  } catch (const mpm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("more than the 4194304 one process can index"), std::string::npos)
        << e.what();
  }
  mpm::GridGeometry<3> largest = huge;
  largest.cells = {1200, 1200, 1200};  // 151^3 = 3,442,951 tiles
  EXPECT_NO_THROW(mpm::ScatterOrder<3>(largest, 2));
}

TYPED_TEST(TransferTest, g2p_reproduces_linear_velocity_field_and_its_gradient) {
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  const mpm::GridGeometry<Dim> geo = test_geometry<Dim, Kernel>();
  const std::vector<mpm::NeoHookean> materials = {mpm::NeoHookean::from_young_poisson(1e6, 0.3, 1e3)};
  // Displacements stay below dt (|v0| + |L| |x|) < 0.1 h, so no particle leaves the domain.
  const Real dt = 1e-3;
  std::mt19937_64 rng(2000 + Dim);
  std::uniform_real_distribution<Real> sym(-1.0, 1.0);

  // v(x) = v0 + L x at every node, ghosts included.
  Vec<Dim> v0;
  Mat<Dim> L;
  for (int a = 0; a < Dim; ++a) {
    v0[a] = sym(rng);
    for (int b = 0; b < Dim; ++b) L(a, b) = sym(rng);
  }
  mpm::Grid<Dim> grid(geo);
  Real v_max = 0, x_max = 0;
  for (std::size_t n = 0; n < grid.size(); ++n) {
    const Vec<Dim> xn = geo.position(geo.coords(static_cast<std::ptrdiff_t>(n)));
    grid.nodes[n].v_new = v0 + L * xn;
    v_max = std::max(v_max, grid.nodes[n].v_new.cwiseAbs().maxCoeff());
    x_max = std::max(x_max, xn.cwiseAbs().maxCoeff());
  }
  int nodes = 1;
  for (int d = 0; d < Dim; ++d) nodes *= Kernel::width;
  // Round-off bounds. Positions are stored in double (a few ulps of |x|) and the gathered velocity sums
  // `nodes` terms of size <= v_max. The velocity gradient sums `nodes` terms of size <= v_max / h that cancel
  // down to L, so its round-off is ~ nodes * eps * v_max / h; F adds a few ulps of |F_old|.
  const Real tol_x = 4 * kEps * x_max + dt * 2 * nodes * kEps * v_max;
  const Real tol_F = 8 * kEps + dt * 2 * nodes * kEps * v_max / geo.h;

  for (Real fraction : half_length_fractions<Kernel>()) {
    SCOPED_TRACE(::testing::Message() << "l_p/h = " << fraction);
    // Away from the boundaries by one cell, with a random F_old near the identity (checks the order of the
    // product in Eq. 11).
    mpm::ParticleSet<Dim> p = random_particles(geo, geo.h, fraction, rng);
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int a = 0; a < Dim; ++a)
        for (int b = 0; b < Dim; ++b) p.F[i](a, b) += 0.1 * sym(rng);
    const mpm::ParticleSet<Dim> before = p;
    const Transfer<Dim, Kernel> t(p, geo);

    if constexpr (mpm::moves_corners<Kernel>)  // CPDI2 moves the corners first, and the particle to their
                                               // centroid
      mpm::g2p_corners(t.stencils(), grid, &mpm::GridNode<Dim>::v_new, dt, p.corners, p.corners);
    const mpm::ParticleFault fault =
        mpm::g2p<mpm::Gather{.velocity = false, .position = true, .deformation = true}>(
            p, t.stencils(), grid, &mpm::GridNode<Dim>::v_new, dt, mpm::NeoHookeanLanes<Dim>{materials});
    EXPECT_FALSE(fault) << "particle " << fault.index;

    for (std::size_t i = 0; i < p.size(); ++i) {
      SCOPED_TRACE(::testing::Message() << "particle " << i << " at " << before.x[i].transpose());
      const Vec<Dim> x_expected = before.x[i] + dt * (v0 + L * before.x[i]);      // Eq. (17)
      const Mat<Dim> F_expected = (Mat<Dim>::Identity() + dt * L) * before.F[i];  // Eq. (11)
      for (int a = 0; a < Dim; ++a) {
        EXPECT_NEAR(p.x[i][a], x_expected[a], tol_x);
        EXPECT_EQ(p.v[i][a], before.v[i][a]);  // velocity not gathered: untouched bit for bit
        for (int b = 0; b < Dim; ++b) EXPECT_NEAR(p.F[i](a, b), F_expected(a, b), tol_F);
      }
      // Eq. (12): V = V0 det F; det is a smooth function of entries of size ~1, so its error is ~Dim tol_F.
      EXPECT_NEAR(p.V[i], before.V0[i] * F_expected.determinant(), before.V0[i] * 4 * Dim * tol_F);
      // CPDI2's corners move with the linear field exactly: x_c + dt (v0 + L x_c).
      if constexpr (mpm::moves_corners<Kernel>)
        for (int c = 0; c < Kernel::corners; ++c) {
          const Vec<Dim> xc = before.corners[i].col(c);
          EXPECT_LT((p.corners[i].col(c) - (xc + dt * (v0 + L * xc))).cwiseAbs().maxCoeff(), tol_x)
              << "corner " << c;
        }
      // G2P writes no half-lengths: the current ones follow from l0 (ParticleSet::half_length).
      EXPECT_EQ(p.l0[i], before.l0[i]);
    }
  }
}

}  // namespace

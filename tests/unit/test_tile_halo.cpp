// The halo sum after P2G (mpm/distributed/tile_halo.hpp): a grid divided into boxes of whole tiles, each box's
// particles scattered into the box's own grid, and the sums of the tiles at its faces added into the nodes they
// share in colour order, gives every node the bits of one process's P2G, for every kernel in 2-D and 3-D and 2 to
// 4 boxes. This is the determinism that the distributed run rests on, checked here in one process.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mpm/distributed/decomposition.hpp"
#include "mpm/distributed/tile_halo.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/p2g.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace {

using mpm::Real;
using mpm::Vec;

template <class K, int D>
struct Case {
  using Kernel = K;
  static constexpr int dim = D;
};
using Cases = ::testing::Types<Case<mpm::LinearKernel, 2>, Case<mpm::LinearKernel, 3>, Case<mpm::GimpKernel, 2>,
                               Case<mpm::GimpKernel, 3>, Case<mpm::QuadraticBSplineKernel, 2>,
                               Case<mpm::QuadraticBSplineKernel, 3>, Case<mpm::CubicBSplineKernel, 2>,
                               Case<mpm::CubicBSplineKernel, 3>>;
struct CaseName {
  template <class C>
  static std::string GetName(int) {
    return std::string(C::Kernel::name) + "_" + std::to_string(C::dim) + "d";
  }
};
template <class C>
class TileHalo : public ::testing::Test {};
TYPED_TEST_SUITE(TileHalo, Cases, CaseName);

/// P2G of mass, momentum and internal force onto a cleared grid, as the explicit step's first scatter; the sums
/// of the face tiles go to `kept` when it is given.
template <int Dim, class Kernel>
void scatter(const mpm::ParticleSet<Dim>& p, mpm::Grid<Dim>& grid, std::vector<mpm::TileSums<Dim>>* kept) {
  std::vector<mpm::Stencil<Dim, Kernel>> stencils;
  std::vector<std::int32_t> tile;
  mpm::build_stencils<Dim, Kernel>(p, grid.geometry, stencils, tile);
  mpm::ScatterOrder<Dim> order(grid.geometry, Kernel::width);
  order.build(tile, p.id);
  const mpm::FaceTileSums<Dim> keep(grid.geometry, order);
  mpm::p2g_add_keeping(keep, stencils, order, grid, mpm::Momentum<Dim>{p.m, p.v},
                       mpm::InternalForce<Dim, mpm::SymTensor<Dim>>{p.V, p.sigma});
  if (kept) *kept = keep.take();
}

TYPED_TEST(TileHalo, BoxesGiveEveryNodeTheBitsOfOneProcess) {
  using Kernel = typename TypeParam::Kernel;
  constexpr int Dim = TypeParam::dim;
  mpm::IVec<Dim> cells;
  cells.fill(Dim == 2 ? 37 : 19);  // 5 x 5 or 3 x 3 x 3 tiles
  Vec<Dim> lo;
  for (int d = 0; d < Dim; ++d) lo[d] = -0.35 + 0.3 * d;
  const mpm::GridGeometry<Dim> geo{lo, 0.1, cells, Kernel::ghost};
  // Particles anywhere in the domain, boundaries included, with random masses, velocities and stresses.
  std::mt19937_64 rng(4000 + Dim);
  std::uniform_real_distribution<Real> unit(0.0, 1.0), sym(-1.0, 1.0);
  mpm::ParticleSet<Dim> p;
  for (int k = 0; k < (Dim == 2 ? 3000 : 6000); ++k) {
    Vec<Dim> x, v;
    for (int d = 0; d < Dim; ++d) {
      x[d] = geo.lo[d] + unit(rng) * geo.h * geo.cells[d];
      v[d] = sym(rng);
    }
    p.add(x, v, 1e-3 * (0.5 + unit(rng)), 1e-4, Vec<Dim>::Constant(0.25 * geo.h), 0);
    for (Real& c : p.sigma.back().c) c = 1e3 * sym(rng);
  }
  mpm::Grid<Dim> one(geo);
  scatter<Dim, Kernel>(p, one, nullptr);

  // The particles of each tile, the weights of the division.
  std::vector<mpm::Stencil<Dim, Kernel>> stencils;
  std::vector<std::int32_t> tile;
  mpm::build_stencils<Dim, Kernel>(p, geo, stencils, tile);
  mpm::IVec<Dim> tiles;
  for (int d = 0; d < Dim; ++d) tiles[d] = geo.tiles_along(d);
  std::vector<std::int64_t> weight(geo.tile_count(), 0);
  for (std::int32_t t : tile) ++weight[static_cast<std::size_t>(t)];

  for (int ranks = 2; ranks <= 4; ++ranks) {
    SCOPED_TRACE(std::to_string(ranks) + " boxes");
    const std::vector<mpm::TileBox<Dim>> boxes = mpm::bisect<Dim>(tiles, weight, ranks);
    std::vector<mpm::Grid<Dim>> grids;
    std::vector<std::vector<mpm::TileSums<Dim>>> kept(boxes.size());
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      mpm::ParticleSet<Dim> q;  // the box's particles, in id order
      for (std::size_t i = 0; i < p.size(); ++i) {
        mpm::IVec<Dim> t;
        std::int32_t rest = tile[i];
        for (int d = 0; d < Dim; ++d) {
          t[d] = rest % tiles[d];
          rest /= tiles[d];
        }
        if (!boxes[b].contains(t)) continue;
        q.add(p.x[i], p.v[i], p.m[i], p.V0[i], p.l[i], 0);
        q.sigma.back() = p.sigma[i];
      }
      grids.emplace_back(mpm::box_geometry<Dim>(geo, boxes[b], Kernel::width));
      scatter<Dim, Kernel>(q, grids.back(), &kept[b]);
    }
    // Compare each box's owned nodes with one process's, before and after the halo sum.
    const auto differing = [&] {
      std::size_t owned = 0, differ = 0;
      for (std::size_t b = 0; b < boxes.size(); ++b) {
        const mpm::GridGeometry<Dim>& bg = grids[b].geometry;
        for (std::size_t n = 0; n < grids[b].size(); ++n) {
          mpm::IVec<Dim> s = bg.coords(static_cast<std::ptrdiff_t>(n));
          for (int d = 0; d < Dim; ++d) s[d] += bg.ghost + bg.offset[d];  // global storage layer
          if (mpm::owner_of<Dim>(s, boxes) != static_cast<int>(b)) continue;
          ++owned;
          mpm::IVec<Dim> i;
          for (int d = 0; d < Dim; ++d) i[d] = s[d] - geo.ghost;
          const mpm::GridNode<Dim>& a = grids[b].nodes[n];
          const mpm::GridNode<Dim>& e = one.nodes[static_cast<std::size_t>(geo.flat(i))];
          differ += a.m != e.m || a.v != e.v || a.a != e.a;
        }
      }
      EXPECT_EQ(owned, one.size());  // every node owned by exactly one box
      return differ;
    };
    const std::size_t before = differing();
    std::vector<mpm::Grid<Dim>*> pointers;
    for (auto& g : grids) pointers.push_back(&g);
    mpm::sum_into_owners<Dim>(boxes, pointers, kept);
    EXPECT_GT(before, 0u) << "the boxes' own sums alone must miss the shared nodes";
    EXPECT_EQ(differing(), 0u);
  }
}

}  // namespace

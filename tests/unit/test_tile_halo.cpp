// The halo sum after P2G (BoxHalo::sum): a grid divided into boxes of whole tiles, each box's particles
// scattered into the box's own grid, and the sums of the tiles at its faces exchanged and added into the
// nodes they share in colour order, gives every node of every box's grid the bits of one process's P2G, for
// every kernel in 2-D and 3-D and 2 to 4 boxes. This is the determinism that the distributed run rests on,
// checked here in one process with a thread per rank.
#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "kernel_cases.hpp"
#include "mpm/distributed/box_halo.hpp"
#include "mpm/distributed/decomposition.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/p2g.hpp"
#include "mpm/transfer/scatter_order.hpp"

namespace {

using mpm::Real;
using mpm::Vec;

using Cases = mpm::testing::KernelCases2D3D;
using CaseName = mpm::testing::KernelCaseName;
template <class C>
class TileHalo : public ::testing::Test {};
TYPED_TEST_SUITE(TileHalo, Cases, CaseName);

/// Ranks played by threads of one process: their exchange() and exchange_with() meet at a barrier; the other
/// operations, which BoxHalo::sum does not call, return this rank's own argument.
class ThreadRanks {
 public:
  explicit ThreadRanks(int size) : mail_(static_cast<std::size_t>(size)), sync_(size) {}

  class Rank final : public mpm::Alone {
   public:
    Rank(ThreadRanks& all, int rank) : mpm::Alone(rank, static_cast<int>(all.mail_.size())), all_(all) {}
    std::vector<std::vector<std::byte>> exchange(
        const std::vector<std::vector<std::byte>>& to) const override {
      all_.mail_[static_cast<std::size_t>(rank())] = to;
      all_.sync_.arrive_and_wait();
      std::vector<std::vector<std::byte>> from;
      for (const auto& sent : all_.mail_) from.push_back(sent[static_cast<std::size_t>(rank())]);
      all_.sync_.arrive_and_wait();  // every rank has read its mail before the next exchange writes
      return from;
    }
    std::vector<std::vector<std::byte>> exchange_with(
        const std::vector<int>& peers, const std::vector<std::vector<std::byte>>& to) const override {
      std::vector<std::vector<std::byte>> all(all_.mail_.size());
      for (std::size_t k = 0; k < peers.size(); ++k) all[static_cast<std::size_t>(peers[k])] = to[k];
      const std::vector<std::vector<std::byte>> received = exchange(all);
      std::vector<std::vector<std::byte>> from;
      for (int r : peers) from.push_back(received[static_cast<std::size_t>(r)]);
      return from;
    }

   private:
    ThreadRanks& all_;
  };

 private:
  std::vector<std::vector<std::vector<std::byte>>> mail_;  ///< mail_[from][to]
  std::barrier<> sync_;
};

/// P2G of mass, momentum and internal force onto a cleared grid, as the explicit step's first scatter; the
/// sums of the face tiles go to `kept` when it is given.
template <int Dim, class Kernel>
void scatter(const mpm::ParticleSet<Dim>& p, mpm::Grid<Dim>& grid, std::vector<mpm::TileSums<Dim>>* kept) {
  std::vector<mpm::StoredStencil<Dim, Kernel>> stencils;
  mpm::build_stencils<Dim, Kernel>(p, grid.geometry, stencils);
  mpm::ScatterOrder<Dim> order(grid.geometry, Kernel::width);
  order.build(mpm::StencilTiles<Dim, Kernel>{stencils}, p.id);
  const mpm::FaceTileSums<Dim> keep(grid.geometry, order);
  mpm::p2g_add_keeping(keep, mpm::ParticleStencils<Dim, Kernel>{stencils, p}, order, 0, grid,
                       mpm::Momentum<Dim>{p.m, p.v},
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
  mpm::place_corners(p);  // CPDI2's domains
  mpm::Grid<Dim> one(geo);
  scatter<Dim, Kernel>(p, one, nullptr);

  // The particles of each tile, the weights of the division.
  std::vector<mpm::StoredStencil<Dim, Kernel>> stencils;
  mpm::build_stencils<Dim, Kernel>(p, geo, stencils);
  const mpm::StencilTiles<Dim, Kernel> tile{stencils};
  mpm::IVec<Dim> tiles;
  for (int d = 0; d < Dim; ++d) tiles[d] = geo.tiles_along(d);
  std::vector<std::int64_t> weight(geo.tile_count(), 0);
  for (std::size_t i = 0; i < tile.size(); ++i) ++weight[static_cast<std::size_t>(tile[i])];

  const auto differing = [&](const mpm::Grid<Dim>& grid) {  // nodes of a box's grid unlike one process's
    std::size_t differ = 0;
    for (std::size_t n = 0; n < grid.size(); ++n) {
      mpm::IVec<Dim> i = grid.geometry.coords(static_cast<std::ptrdiff_t>(n));
      for (int d = 0; d < Dim; ++d) i[d] += grid.geometry.offset[d];
      const mpm::GridNode<Dim>& a = grid.nodes[n];
      const mpm::GridNode<Dim>& e = one.nodes[static_cast<std::size_t>(geo.flat(i))];
      differ += a.m != e.m || a.v != e.v || a.a != e.a;
    }
    return differ;
  };
  for (int ranks = 2; ranks <= 4; ++ranks) {
    SCOPED_TRACE(std::to_string(ranks) + " boxes");
    const std::vector<mpm::TileBox<Dim>> boxes = mpm::bisect<Dim>(tiles, weight, ranks);
    ThreadRanks world(ranks);
    std::vector<std::size_t> before(boxes.size()), after(boxes.size()), nodes(boxes.size());
    std::vector<std::vector<int>> peers(boxes.size());
    std::vector<std::thread> threads;
    for (int b = 0; b < ranks; ++b)
      threads.emplace_back([&, b] {
        const mpm::BoxHalo<Dim> halo(geo, boxes, b, Kernel::width);
        peers[static_cast<std::size_t>(b)] = halo.peers();
        mpm::ParticleSet<Dim> q;  // the box's particles, in id order
        for (std::size_t i = 0; i < p.size(); ++i) {
          mpm::IVec<Dim> t;
          std::int32_t rest = tile[i];
          for (int d = 0; d < Dim; ++d) {
            t[d] = rest % tiles[d];
            rest /= tiles[d];
          }
          if (!boxes[static_cast<std::size_t>(b)].contains(t)) continue;
          q.add(p.x[i], p.v[i], p.m[i], p.V0[i], p.l0[i], 0);
          q.sigma.back() = p.sigma[i];
          q.corners.push_back(p.corners[i]);
        }
        mpm::Grid<Dim> grid(halo.box());
        std::vector<mpm::TileSums<Dim>> kept;
        scatter<Dim, Kernel>(q, grid, &kept);
        const auto k = static_cast<std::size_t>(b);
        before[k] = differing(grid);
        halo.sum(grid, std::move(kept), true, true, ThreadRanks::Rank(world, b));
        after[k] = differing(grid);
        nodes[k] = grid.size();
      });
    for (std::thread& t : threads) t.join();
    std::size_t missed = 0;
    for (int b = 0; b < ranks; ++b) {
      const auto k = static_cast<std::size_t>(b);
      missed += before[k];
      EXPECT_GT(nodes[k], 0u) << "box " << b;
      EXPECT_EQ(after[k], 0u) << "box " << b << ": nodes unlike one process's after the halo sum";
    }
    EXPECT_GT(missed, 0u) << "the boxes' own sums alone must miss the shared nodes";
    // Neighbours are mutual, and no box its own.
    for (int b = 0; b < ranks; ++b)
      for (int c : peers[static_cast<std::size_t>(b)]) {
        EXPECT_NE(c, b);
        const std::vector<int>& back = peers[static_cast<std::size_t>(c)];
        EXPECT_TRUE(std::find(back.begin(), back.end(), b) != back.end()) << b << " and " << c;
      }
  }
}

}  // namespace

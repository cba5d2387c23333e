// A particle centre the nodes carry past a wall face is put back on its plane (GridGeometry::walls); past a
// free face it has left the grid. uGIMP: the weights of a particle on the wall reach the nodes inside the
// material.
#include <gtest/gtest.h>

#include <vector>

#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernels.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/g2p_stress.hpp"

namespace {

using mpm::Real;
using mpm::Vec;

/// One particle (half-length h/4) with its centre 1e-9 m above the face y = 0 of a 4 x 4 grid (h = 0.1) whose
/// nodes all move at (0.2, -1) m/s, moved over dt = 1e-3 s: 1e-3 m down. The fault G2P reports, and the
/// position.
std::pair<bool, Vec<2>> moved(bool wall) {
  mpm::GridGeometry<2> geo{Vec<2>(0, 0), 0.1, mpm::IVec<2>{4, 4}, mpm::GimpKernel::ghost};
  geo.walls[2] = wall;
  mpm::Grid<2> grid(geo);
  for (auto& node : grid.nodes) {
    node.m = 1;
    node.v_new = Vec<2>(0.2, -1);
  }
  mpm::ParticleSet<2> p;
  p.add(Vec<2>(0.15, 1e-9), Vec<2>::Zero(), 1, 1e-2, Vec<2>::Constant(0.025), 0);
  std::vector<mpm::StoredStencil<2, mpm::GimpKernel>> stencils;
  mpm::build_stencils<2, mpm::GimpKernel>(p, geo, stencils);
  const mpm::ParticleFault fault =
      mpm::g2p<mpm::Gather{.velocity = false, .position = true, .deformation = false}>(
          p, mpm::ParticleStencils<2, mpm::GimpKernel>{stencils, p}, grid, &mpm::GridNode<2>::v_new, 1e-3,
          mpm::NoStress{});
  return {static_cast<bool>(fault), p.x[0]};
}

TEST(Walls, ACentreCarriedPastAWallStaysOnItsPlane) {
  const auto [fault, x] = moved(true);
  EXPECT_FALSE(fault);
  EXPECT_EQ(x[1], 0.0);                   // on the wall
  EXPECT_NEAR(x[0], 0.15 + 2e-4, 1e-15);  // and free along it
}

TEST(Walls, ACentreCarriedPastAFreeFaceHasLeftTheGrid) {
  const auto [fault, x] = moved(false);
  EXPECT_TRUE(fault);
  EXPECT_NEAR(x[1], 1e-9 - 1e-3, 1e-15);
}

TEST(Walls, OntoWallsMovesOnlyWhatLiesBeyondAWall) {
  mpm::GridGeometry<2> geo{Vec<2>(0, 0), 0.1, mpm::IVec<2>{4, 4}, 1};
  geo.walls = {false, true, true, false};  // x-max and y-min
  EXPECT_EQ(geo.onto_walls(Vec<2>(0.5, -0.1)), Vec<2>(0.4, 0.0));
  EXPECT_EQ(geo.onto_walls(Vec<2>(-0.1, 0.5)), Vec<2>(-0.1, 0.5));
  EXPECT_EQ(geo.onto_walls(Vec<2>(0.2, 0.3)), Vec<2>(0.2, 0.3));
}

}  // namespace

// The lattice surface of a body (particles/surface.hpp) and the force and moment of a surface load on one
// patch (boundary/surface_loads.hpp), against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mpm/boundary/surface_loads.hpp"
#include "mpm/particles/generate.hpp"
#include "mpm/particles/surface.hpp"

namespace {

using mpm::Mat;
using mpm::Vec;

std::vector<Vec<2>> area_vectors(const std::vector<mpm::LatticeFaces<2>>& faces) {
  std::vector<Vec<2>> a;
  for (const mpm::LatticeFaces<2>& f : faces) a.push_back(mpm::area_vector<2>(f));
  return a;
}

TEST(LatticeSurface, ABoxShowsItsFacesAndItsCornersBothFaces) {
  // 4 x 3 particles at spacing 0.5: 10 of the 12 are on the surface; the x-max column's vectors sum to (3 s,
  // 0), the corners carry two faces each, and all the vectors sum to zero.
  mpm::ParticleSet<2> p;
  mpm::fill_box<2>(p, Vec<2>(0, 0), Vec<2>(2, 1.5), 0.5, 1, 0);
  const std::vector<Vec<2>> a = area_vectors(mpm::lattice_surface<2>(p.X, p.X.front(), 0.5));
  Vec<2> total = Vec<2>::Zero(), right = Vec<2>::Zero();
  int surface = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    total += a[i];
    if (p.X[i][0] > 1.7) right += a[i];
    if (!a[i].isZero(0)) ++surface;
    if (p.X[i][0] < 0.3 && p.X[i][1] < 0.3) {
      EXPECT_EQ(a[i], Vec<2>(-0.5, -0.5));
    }
  }
  EXPECT_EQ(surface, 10);
  EXPECT_EQ(total, Vec<2>::Zero());
  EXPECT_EQ(right, Vec<2>(1.5, 0));
}

TEST(LatticeSurface, ADisksRightHalfShowsItsProjectedHeight) {
  // A disk of radius 1 on a lattice of spacing 0.05: the x-components of the right half's vectors sum to the
  // height the lattice covers there (one s per occupied row), and the vectors of the whole disk sum to zero.
  mpm::ParticleSet<2> p;
  mpm::fill_box<2>(p, Vec<2>(-1, -1), Vec<2>(1, 1), 0.05, 1, 0, {},
                   [](const Vec<2>& x) { return x.norm() <= 1; });
  const std::vector<Vec<2>> a = area_vectors(mpm::lattice_surface<2>(p.X, p.X.front(), 0.05));
  double right = 0, rows = 0;
  Vec<2> total = Vec<2>::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) {
    total += a[i];
    if (a[i][0] > 0) right += a[i][0];
  }
  for (int k = 0; k < 40; ++k)
    rows += std::abs(-1 + (k + 0.5) * 0.05) <= 1 ? 0.05 : 0;  // every row holds particles
  EXPECT_NEAR(right, rows, 1e-12);
  EXPECT_NEAR(total.norm(), 0, 1e-12);
}

TEST(LatticeSurface, AxisymmetricFacesCarryTheirRadius) {
  // One row of 2 particles at r = 0.25, 0.75 (spacing 0.5) in axisymmetry: the outer radial face lies at r =
  // 1, the inner at r = 0 (area 0); each z-face of the cell at X_r has area X_r s.
  mpm::ParticleSet<2> p;
  mpm::fill_box<2>(p, Vec<2>(0, 0), Vec<2>(1, 0.5), 0.5, 1, 0);
  const std::vector<mpm::LatticeFaces<2>> f = mpm::lattice_surface<2>(p.X, p.X.front(), 0.5, true);
  EXPECT_NEAR(f[0][0], 0, 1e-15);           // inner face at r = 0
  EXPECT_NEAR(f[1][1], 1.0 * 0.5, 1e-15);   // outer face at r = 1
  EXPECT_EQ(f[0][1], 0);                    // faces the other particle
  EXPECT_NEAR(f[0][2], 0.25 * 0.5, 1e-15);  // z-min and z-max: X_r s each
  EXPECT_NEAR(f[0][3], 0.25 * 0.5, 1e-15);
  EXPECT_NEAR(mpm::area_vector<2>(f[0])[1], 0, 1e-15);  // they cancel in the area vector
}

TEST(PatchLoad, PressureTurnsAndStretchesWithTheBodyAndATractionDoesNot) {
  // F = R(theta) diag(1, 2): the reference face N dA = e_x (area 1) has n da = J F^-T e_x = 2 R e_x (the face
  // stretched twice along its length), so P = 3 gives -6 (cos, sin); the dead traction t = (1, 2) gives t |N
  // dA|. The moments, with the faces half a spacing (0.25) from the centre: the force (x) 0.25 e_x for the
  // pressure, t (x) 0.25 N dA for the traction.
  const double c = std::cos(0.3), s = std::sin(0.3);
  Mat<2> R;
  R << c, -s, s, c;
  const Mat<2> F = R * Vec<2>(1, 2).asDiagonal();
  mpm::SurfaceLoad<2> pressure;
  pressure.pressure = [](double) { return 3.0; };
  const mpm::SurfacePatch<2> x_max{0, {0, 1, 0, 0}, 0.25}, y_max{0, {0, 0, 0, 0.5}, 0.25};
  const mpm::PatchLoad<2> f =
      mpm::patch_load<2>(pressure, 3, Vec<2>::Zero(), x_max, F, Vec<2>(1, 1), Vec<2>(1, 1), false);
  EXPECT_NEAR(f.force[0], -6 * c, 1e-14);
  EXPECT_NEAR(f.force[1], -6 * s, 1e-14);
  EXPECT_NEAR(f.moment(0, 0), -1.5 * c, 1e-14);
  EXPECT_NEAR(f.moment(1, 0), -1.5 * s, 1e-14);
  EXPECT_EQ(f.moment.col(1), Vec<2>::Zero());
  mpm::SurfaceLoad<2> traction;
  traction.traction = [](double) { return Vec<2>(1, 2); };
  const mpm::PatchLoad<2> t =
      mpm::patch_load<2>(traction, 0, Vec<2>(1, 2), y_max, F, Vec<2>(1, 1), Vec<2>(1, 1), false);
  EXPECT_EQ(t.force, Vec<2>(0.5, 1));
  Mat<2> moment;
  moment << 0, 0.125, 0, 0.25;
  EXPECT_EQ(t.moment, moment);
  // Axisymmetry: the hoop stretch x_r / X_r = 1.5 multiplies the current area.
  const mpm::PatchLoad<2> g = mpm::patch_load<2>(pressure, 3, Vec<2>::Zero(), x_max, Mat<2>::Identity(),
                                                 Vec<2>(1.5, 0), Vec<2>(1, 0), true);
  EXPECT_NEAR(g.force[0], -4.5, 1e-14);
  EXPECT_NEAR(g.force[1], 0, 1e-14);
  // A particle one lattice cell thick pressed on both x-faces: no force, the moment squeezes it.
  const mpm::PatchLoad<2> both = mpm::patch_load<2>(pressure, 3, Vec<2>::Zero(), {0, {1, 1, 0, 0}, 0.25},
                                                    Mat<2>::Identity(), Vec<2>(1, 1), Vec<2>(1, 1), false);
  EXPECT_EQ(both.force, Vec<2>::Zero());
  EXPECT_EQ(both.moment(0, 0), -1.5);
}

TEST(SurfaceLoadSet, AddsForcesAndMomentsToTheLoadedParticlesByTheirIds) {
  // Three particles of mass 2 stored in the order of ids 2, 0, 1; a pressure of 4 on ids 0 and 2 (face x-max,
  // area 1) and a traction (0, 1) on id 2 (face y-max, area 0.5), half a spacing 0.5 from the centres: weight
  // 0.5.
  mpm::ParticleSet<2> p;
  for (int k = 0; k < 3; ++k) p.add(Vec<2>(k + 1, 0), Vec<2>::Zero(), 2, 1, Vec<2>::Constant(0.5), 0);
  p.id = {2, 0, 1};
  mpm::SurfaceLoad<2> pressure;
  pressure.pressure = [](double t) { return 4 * t; };
  pressure.patches = {{0, {0, 1, 0, 0}, 0.5}, {2, {0, 1, 0, 0}, 0.5}};
  mpm::SurfaceLoad<2> traction;
  traction.traction = [](double) { return Vec<2>(0, 1); };
  traction.patches = {{2, {0, 0, 0, 0.5}, 0.5}};
  const mpm::SurfaceLoads<2> loads({pressure, traction});
  mpm::SurfaceLoading<2> loading;
  loading.reset(p);
  loads.add_to_particles(p, 1.0, 0.5, mpm::Geometry::plane_strain, loading);
  EXPECT_EQ(loading.force[0], Vec<2>(-2, 0.25));  // id 2: 0.5 (-4, 0) + 0.5 (0, 0.5)
  EXPECT_EQ(loading.force[1], Vec<2>(-2, 0));     // id 0
  EXPECT_EQ(loading.force[2], Vec<2>(0, 0));      // id 1: not loaded
  // The moments, weighted alike: id 2's 0.5 ((-4, 0) (x) 0.5 e_x + (0, 1) (x) 0.5 (0, 0.5)).
  EXPECT_EQ(loading.moment[0], (Mat<2>() << -1, 0, 0, 0.125).finished());
  EXPECT_EQ(loading.moment[1], (Mat<2>() << -1, 0, 0, 0).finished());
  EXPECT_EQ(loading.moment[2], Mat<2>::Zero());
  // Their work as the particles move and deform: id 2 moved by (0.1, 0.2) and F went from I to diag(1.1, 1):
  // f . dx + (F - I) : A = -0.2 + 0.05 - 0.1; across a periodic face of period 1 (x-axis), a move of -0.9 is
  // one of +0.1.
  loading.start(p);
  mpm::GridGeometry<2> g;
  g.h = 0.25;
  g.cells = {4, 4};
  p.x[0] += Vec<2>(0.1, 0.2);
  p.F[0] = Vec<2>(1.1, 1).asDiagonal();
  EXPECT_NEAR(loading.work(p, 0, g), -0.25, 1e-15);
  g.periodic = {true, false};
  p.x[0][0] -= 1;
  EXPECT_NEAR(loading.work(p, 0, g), -0.25, 1e-15);
  EXPECT_EQ(loading.work(p, 2, g), 0);
}

}  // namespace

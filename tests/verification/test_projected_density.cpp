// Projected density of a constant-density bar (Steffen et al. 2008, Sec. 4.3, Fig. 7): how far each kernel
// spreads material beyond the body. Expected values are hand-computed from the bases, in units of h.
#include <gtest/gtest.h>

#include <algorithm>

#include "mpm/verification/projected_density.hpp"

namespace mpm {
namespace {

struct Expected {
  KernelKind kernel;
  Real support_cells;  ///< the field reaches this many cells beyond each end of the body
  Real l1_cells;       ///< int |rho - 1| over the grid [-0.2, 1.2], in units of h
};

// Every loaded node has rho_i = m_i / V_i = 1 exactly, so rho(x) = sum over loaded nodes of phi_i(x): 1 inside
// the body (partition of unity) and a tail outside. With 3 particles per cell the outermost particle sits h/6
// inside the body, so the loaded nodes are those within the particle weight's radius of it:
// - linear and GIMP (grid basis: linear hat): nodes 0..N; tail int_{-h}^0 phi_0 = h/2 per side.
// - quadratic B-spline (radius 1.5h): nodes -1..N+1; per side int_{-inf}^0 (phi_{-1} + phi_0 + phi_1) =
//   h (1 - 1/48) + h/2 + h/48 = 1.5 h, minus the part beyond the grid end at -2h, int_{1h}^{1.5h} of the
//   node -1 tail = h/48.
// - cubic B-spline (radius 2h): nodes -1..N+1; per side (1 - 1/24) h + h/2 + h/24 = 1.5 h, minus the part
//   beyond -2h, h/24.
const Expected expected[] = {
    {KernelKind::linear, 1.0, 2 * 0.5},
    {KernelKind::ugimp, 1.0, 2 * 0.5},
    {KernelKind::cpgimp, 1.0, 2 * 0.5},
    {KernelKind::bspline2, 2.5, 2 * (1.5 - 1.0 / 48)},
    {KernelKind::bspline3, 3.0, 2 * (1.5 - 1.0 / 24)},
};

TEST(ProjectedDensity, SupportAndL1ErrorMatchTheBases) {
  for (const Expected& e : expected) {
    SCOPED_TRACE(std::string(to_string(e.kernel)));
    const DensityProjection d = project_density_1d(e.kernel, 10, 3, 14000);
    EXPECT_NEAR(d.support_lo, -e.support_cells * d.h, 1e-12);
    EXPECT_NEAR(d.support_hi, 1 + e.support_cells * d.h, 1e-12);
    // Midpoint rule over 14000 intervals on a piecewise polynomial: error O(dx^2) at each kink, dx = 1e-4.
    EXPECT_NEAR(d.l1_error, e.l1_cells * d.h, 1e-7);
    for (Real rho : d.node_density) EXPECT_NEAR(rho, 1.0, 1e-14);
    for (std::size_t k = 0; k < d.sample_x.size(); ++k)
      if (d.sample_x[k] > 0 && d.sample_x[k] < 1) {
        ASSERT_NEAR(d.sample_density[k], 1.0, 1e-14);
      }
  }
}

TEST(ProjectedDensity, GeometricErrorIsFirstOrderInH) {
  // Steffen et al. 2008 Sec. 4.3: the geometric error is O(h) for every kernel; halving h halves it. From
  // h = 1/20 on, no tail reaches past the grid end at -0.2, so the ratio is exactly 2.
  for (KernelKind k : {KernelKind::linear, KernelKind::bspline2, KernelKind::bspline3}) {
    const Real coarse = project_density_1d(k, 20, 3, 14000).l1_error;
    const Real fine = project_density_1d(k, 40, 3, 28000).l1_error;
    EXPECT_NEAR(coarse / fine, 2.0, 1e-5);
  }
}

}  // namespace
}  // namespace mpm

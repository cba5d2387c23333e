// Projected density of a constant-density bar (Steffen et al. 2008, Sec. 4.3, Fig. 7): how far each kernel
// spreads material beyond the body. Expected values are hand-computed from the bases, in units of h.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>

#include "mpm/verification/projected_density.hpp"

namespace mpm {
namespace {

/// The bar with 3 particles per cell.
DensityCase bar(KernelKind kernel, int cells, int samples) {
  DensityCase c;
  c.kernel = kernel;
  c.cells = cells;
  c.ppc = 3;
  c.samples = samples;
  return c;
}

struct Expected {
  KernelKind kernel;
  Real support_cells;  ///< the field reaches this many cells beyond each end of the body
  Real l1_cells;       ///< int |rho - 1| over the grid [-0.2, 1.2], in units of h
};

// Every loaded node has rho_i = m_i / V_i = 1 exactly, so rho(x) = sum over loaded nodes of phi_i(x): 1
// inside the body (partition of unity) and a tail outside. With 3 particles per cell the outermost particle
// sits h/6 inside the body, so the loaded nodes are those within the particle weight's radius of it:
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
    const DensityProjection d = project_density_1d(bar(e.kernel, 10, 14000));
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
    const Real coarse = project_density_1d(bar(k, 20, 14000)).l1_error;
    const Real fine = project_density_1d(bar(k, 40, 28000)).l1_error;
    EXPECT_NEAR(coarse / fine, 2.0, 1e-5);
  }
}

// The boundary-aligned case (Steffen et al. 2008, Sec. 4.3): the grid is the bar [0, 1] itself. Linear MPM
// and GIMP with the particles' own width project nothing beyond it: the outermost particle sits l_p/2 inside
// the end, and the extra node h outside is h + l_p/2 from it, where its GIMP weight reaches zero. uGIMP with
// a smoothing length wider than the particles, and both B-splines, load the extra nodes. With 3 particles per
// cell (m_p = h/3, the outermost at h/6, 3h/6, 5h/6, ...), per end:
// - quadratic B-spline, and uGIMP with l = h (the same basis): only the outermost particle reaches the node
// at
//   -h, at 7h/6 with weight (1.5 - 7/6)^2 / 2 = 1/18: mass h/54.
// - cubic B-spline: the node at -h gets (2 - r/h)^3 / 6 from r = 7h/6, 9h/6 and 11h/6, i.e.
//   (125 + 27 + 1) / 1296 = 153/1296; the node at -2h is beyond 2h of every particle: mass (h/3) 153/1296.
// - clamped B-splines: no node beyond the faces, so none.
TEST(ProjectedDensity, BoundaryAlignedExtraNodesGetMassOnlyFromWideBases) {
  const Real h = 0.1;
  struct Aligned {
    const char* name;
    KernelKind kernel;
    std::optional<Real> gimp_length;
    Real outside_mass;
  };
  for (const Aligned& a :
       {Aligned{"linear", KernelKind::linear, {}, 0.0}, Aligned{"cpgimp", KernelKind::cpgimp, {}, 0.0},
        Aligned{"ugimp, l = l_p", KernelKind::ugimp, {}, 0.0},
        Aligned{"ugimp, l = h", KernelKind::ugimp, h, 2 * h / 54},
        Aligned{"bspline2", KernelKind::bspline2, {}, 2 * h / 54},
        Aligned{"bspline3", KernelKind::bspline3, {}, 2 * (h / 3) * 153.0 / 1296},
        // The clamped splines have no node beyond the grid's faces (docs/kernels.md).
        Aligned{"bspline2-clamped", KernelKind::bspline2_clamped, {}, 0.0},
        Aligned{"bspline3-clamped", KernelKind::bspline3_clamped, {}, 0.0}}) {
    SCOPED_TRACE(a.name);
    DensityCase c = bar(a.kernel, 10, 1000);
    c.boundary_aligned = true;
    c.gimp_length = a.gimp_length;
    const DensityProjection d = project_density_1d(c);
    EXPECT_NEAR(d.outside_mass, a.outside_mass, 1e-15);
    // Inside the body the field is still exact: every loaded node has rho_i = 1 and the bases are partitions
    // of unity over [0, 1] once the extra nodes are counted.
    EXPECT_LT(d.l1_error, 1e-14);
    if (a.kernel == KernelKind::bspline2_clamped || a.kernel == KernelKind::bspline3_clamped) {
      // Exact up to the faces without any extra node: the field is nonzero on the body alone.
      EXPECT_EQ(d.support_lo, 0.0);
      EXPECT_EQ(d.support_hi, 1.0);
      for (Real x : d.node_x) EXPECT_TRUE(x >= 0 && x <= 1) << x;
    }
  }
}

}  // namespace
}  // namespace mpm

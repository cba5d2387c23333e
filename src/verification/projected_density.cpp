#include "mpm/verification/projected_density.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/generate.hpp"
#include "mpm/shape/stencil.hpp"

namespace mpm {

namespace {
/// The grid basis phi_i a nodal field is reconstructed with: GIMP weights are particle-averaged linear hats
/// (Steffen et al. 2008, Eq. (31)), and CPDI's and CPDI2's average them over the domain's corners (Sadeghirad
/// et al. 2011, 2013), so their grid basis is the hat itself.
template <class Kernel>
using GridBasis = std::conditional_t<std::is_same_v<Kernel, GimpKernel> ||
                                         std::is_same_v<Kernel, WideGimpKernel> || is_cpdi<Kernel>,
                                     LinearKernel, Kernel>;

/// Half-width of a grid basis function in cells.
template <class Basis>
constexpr Real basis_radius() {
  if constexpr (std::is_same_v<Basis, LinearKernel>) return 1;
  if constexpr (std::is_same_v<Basis, QuadraticBSplineKernel>) return 1.5;
  return 2;
}

template <class Kernel>
DensityProjection project(const DensityCase& c) {
  using Basis = GridBasis<Kernel>;
  DensityProjection out;
  out.h = 1.0 / c.cells;
  const int margin =
      c.boundary_aligned ? 0 : c.cells / 5;  // 0.2 / h cells on either side of the bar, or none
  GridGeometry<1> g{Vec<1>(-margin * out.h), out.h, IVec<1>{c.cells + 2 * margin}, Kernel::ghost};
  const BoundarySpec<1> free_faces;
  g.clamped = clamped_faces(c.kernel, free_faces);
  const NodeLayout<1> layout(g);
  ParticleSet<1> p;
  fill_box<1>(p, Vec<1>(0.0), Vec<1>(1.0), out.h / c.ppc, 1.0, 0);
  if (c.gimp_length)
    for (Vec<1>& l : p.l0) l.setConstant(0.5 * *c.gimp_length);
  if constexpr (moves_corners<Kernel>) place_corners(p);  // CPDI2's domains: the particles' segments

  // Nodal mass and volume, m_i = sum_p S_ip m_p and V_i = sum_p S_ip V_p (Steffen et al. 2008, Sec. 4.3).
  std::vector<Real> mass(g.node_count(), 0.0), volume(g.node_count(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    out.particle_x.push_back(p.x[i][0]);
    for_each_node(make_stencil<1, Kernel>(g, layout, p.x[i], domain_of<1, Kernel>(p, i)), layout,
                  [&](std::int32_t n, Real S, const Vec<1>&) {
                    mass[n] += S * p.m[i];
                    volume[n] += S * p.V0[i];
                  });
  }
  std::vector<Real> density(g.node_count(), 0.0);
  Real first = 0, last = 0;
  for (std::size_t n = 0; n < density.size(); ++n) {
    if (!(mass[n] > 0)) continue;
    density[n] = mass[n] / volume[n];
    const Real xn = g.position(g.coords(static_cast<std::ptrdiff_t>(n)))[0];
    if (xn < 0 || xn > 1) out.outside_mass += mass[n];
    if (out.node_x.empty()) first = xn;
    last = xn;
    out.node_x.push_back(xn);
    out.node_density.push_back(density[n]);
  }
  out.support_lo = first - basis_radius<Basis>() * out.h;
  out.support_hi = last + basis_radius<Basis>() * out.h;
  if (g.clamped[0]) out.support_lo = std::max(out.support_lo, g.lo[0]);  // the clamped basis ends on the face
  if (g.clamped[1]) out.support_hi = std::min(out.support_hi, g.hi()[0]);

  // rho(x) = sum_i rho_i phi_i(x) (Steffen et al. 2008, Sec. 4.3), sampled at interval midpoints.
  const Real lo = g.lo[0], width = g.hi()[0] - lo, dx = width / c.samples;
  const Vec<1> no_size(0.0);
  for (int k = 0; k < c.samples; ++k) {
    const Vec<1> x(lo + (k + 0.5) * dx);
    Real rho = 0;
    for_each_node(make_stencil<1, Basis>(g, layout, x, no_size), layout,
                  [&](std::int32_t n, Real phi, const Vec<1>&) { rho += density[n] * phi; });
    out.sample_x.push_back(x[0]);
    out.sample_density.push_back(rho);
    const Real exact = (x[0] >= 0 && x[0] <= 1) ? 1.0 : 0.0;
    out.l1_error += std::abs(rho - exact) * dx;
  }
  return out;
}
}  // namespace

DensityProjection project_density_1d(const DensityCase& c) {
  if (c.cells < 5 || c.cells % 5 != 0) throw InputError("--cells: expected a positive multiple of 5");
  if (c.ppc < 1) throw InputError("--ppc: expected at least 1 particle per cell");
  if (c.samples < 10) throw InputError("--samples: expected at least 10");
  if (c.gimp_length && c.kernel != KernelKind::ugimp)
    throw InputError("--gimp-length: applies to --kernel ugimp only");
  if (c.gimp_length && !(*c.gimp_length > 0 && *c.gimp_length <= 1.0 / c.cells))
    throw InputError("--gimp-length: expected a smoothing length in (0, h], h = 1 / cells");
  return with_kernel<1>(c.kernel, [&]<class Kernel>() { return project<Kernel>(c); });
}

}  // namespace mpm

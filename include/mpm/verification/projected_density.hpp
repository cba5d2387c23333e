#pragma once
/// The projected density field of Steffen et al. 2008, Sec. 4.3 and Fig. 7: a constant-density 1-D bar on
/// [0, 1] in a grid covering [-0.2, 1.2], projected to the nodes and reconstructed with the grid basis. It shows
/// how far each kernel spreads material beyond the body (an O(h) geometric error at boundaries).
#include <vector>

#include "mpm/explicit/spec.hpp"

namespace mpm {

struct DensityProjection {
  Real h = 0;                      ///< cell width [m]
  std::vector<Real> particle_x;    ///< particle positions [m]
  std::vector<Real> node_x;        ///< positions of the nodes that received mass [m]
  std::vector<Real> node_density;  ///< rho_i = m_i / V_i there [kg/m]
  std::vector<Real> sample_x;      ///< sample points, midpoints of equal intervals over the grid [m]
  std::vector<Real> sample_density;  ///< rho(x) = sum_i rho_i phi_i(x) at the samples
  Real support_lo = 0, support_hi = 0;  ///< where rho(x) > 0: outermost loaded node -/+ the basis radius [m]
  Real l1_error = 0;  ///< int |rho(x) - rho_true(x)| dx over the grid, midpoint rule on the samples [kg]
};

/// Project a unit-density bar of `cells` cells per unit length (a multiple of 5, so the grid ends at -0.2 and
/// 1.2) and `ppc` particles per cell with the given kernel; evaluate the field at `samples` points. GIMP
/// kernels reconstruct with their grid basis, the linear hat.
DensityProjection project_density_1d(KernelKind kernel, int cells, int ppc, int samples);

}  // namespace mpm

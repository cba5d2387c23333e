#pragma once
/// The projected density field of Steffen et al. 2008, Sec. 4.3 and Fig. 7: a constant-density 1-D bar on
/// [0, 1] in a grid covering [-0.2, 1.2], projected to the nodes and reconstructed with the grid basis. It
/// shows how far each kernel spreads material beyond the body (an O(h) geometric error at boundaries). In the
/// boundary-aligned case the grid is [0, 1] itself, and what matters is the mass projected to the extra nodes
/// beyond its ends.
#include <optional>
#include <vector>

#include "mpm/explicit/spec.hpp"

namespace mpm {

struct DensityProjection {
  Real h = 0;                           ///< cell width [m]
  std::vector<Real> particle_x;         ///< particle positions [m]
  std::vector<Real> node_x;             ///< positions of the nodes that received mass [m]
  std::vector<Real> node_density;       ///< rho_i = m_i / V_i there [kg/m]
  std::vector<Real> sample_x;           ///< sample points, midpoints of equal intervals over the grid [m]
  std::vector<Real> sample_density;     ///< rho(x) = sum_i rho_i phi_i(x) at the samples
  Real support_lo = 0, support_hi = 0;  ///< where rho(x) > 0: outermost loaded node -/+ the basis radius [m]
  Real l1_error = 0;      ///< int |rho(x) - rho_true(x)| dx over the grid, midpoint rule on the samples [kg]
  Real outside_mass = 0;  ///< mass projected to nodes outside the body [0, 1] [kg]
};

/// One projection: a unit-density bar of `cells` cells per unit length (a multiple of 5, so the grid ends at
/// -0.2 and 1.2, or at 0 and 1 when `boundary_aligned`) and `ppc` particles per cell, the field evaluated at
/// `samples` points.
struct DensityCase {
  KernelKind kernel = KernelKind::linear;
  int cells = 10, ppc = 3, samples = 1400;
  bool boundary_aligned = false;
  /// uGIMP smoothing length l (Steffen et al. 2008, Sec. 4.1); absent: each particle's own width.
  std::optional<Real> gimp_length;
};

/// Project the bar of `c` with its kernel. GIMP kernels reconstruct with their grid basis, the linear hat.
DensityProjection project_density_1d(const DensityCase& c);

}  // namespace mpm

#pragma once
/// Compressible Newtonian fluid of Sulsky & Kaul 2004, Eq. (2.1.7).
#include <algorithm>
#include <cmath>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

/// sigma = -p I + lambda (div v) I + mu (grad v + grad v^T) (Sulsky & Kaul 2004, Eq. (2.1.7)) with the
/// barotropic pressure p = -K ln J (the paper leaves p open; this one is the small-strain K (1 - J) with a
/// finite energy). The stress depends on the state only through J and on the current rate of deformation D =
/// sym(grad v).
struct NewtonianFluid {
  Real mu = 0;      ///< shear viscosity [Pa s]
  Real lambda = 0;  ///< second viscosity [Pa s] (Stokes' hypothesis: -2 mu / 3)
  Real bulk = 0;    ///< bulk modulus K of the pressure [Pa] (0: no pressure)
  Real rho0 = 0;    ///< reference density [kg/m^3]

  /// Sulsky & Kaul 2004, Eq. (2.1.7), with D = (grad v + grad v^T)/2 the 3 x 3 rate of deformation [1/s].
  Mat3 stress(const Mat3& D, Real J) const {
    const Real p = -bulk * std::log(J);
    return (-p + lambda * D.trace()) * Mat3::Identity() + 2 * mu * D;  // Sulsky & Kaul 2004, Eq. (2.1.7)
  }
  /// The acoustic speed sqrt(K / rho) at volume ratio J, rho = rho0 / J. The viscous limit of the explicit
  /// step, dt < rho h^2 / (2 (lambda + 2 mu)), is not in it: give `dt` for viscosity-dominated flows.
  Real wave_speed(Real J) const { return std::sqrt(bulk * J / rho0); }
};

/// Throw InputError naming `where` and the key (density, viscosity, second_viscosity, bulk_modulus).
inline void validate(const NewtonianFluid& f, const std::string& where) {
  if (!(f.rho0 > 0 && std::isfinite(f.rho0)))
    throw InputError(where + ".density: expected a positive density");
  if (!(f.mu >= 0 && std::isfinite(f.mu)))
    throw InputError(where + ".viscosity: expected a viscosity >= 0 [Pa s]");
  if (!(std::isfinite(f.lambda) && 3 * f.lambda + 2 * f.mu >= 0))
    throw InputError(where +
                     ".second_viscosity: expected lambda >= -2 mu / 3 (a non-negative bulk viscosity)");
  if (!(f.bulk >= 0 && std::isfinite(f.bulk)))
    throw InputError(where + ".bulk_modulus: expected K >= 0 [Pa]");
  if (!(f.bulk > 0 || f.mu > 0))
    throw InputError(where + ".viscosity: a fluid needs a viscosity or a bulk modulus");
}

}  // namespace mpm

#pragma once
/// Drucker-Prager plasticity with non-associated flow, a tension cut-off and a return to the apex
/// (de Souza Neto et al. 2008, Sec. 8.3), its cone matched to Mohr-Coulomb's hexagonal pyramid.
///
/// Yield function f = sqrt(J2) + eta p - xi c, plastic potential g = sqrt(J2) + eta_bar p (tension positive,
/// p = tr(sigma) / 3), and the tension cut-off p <= t. The return works in the (p, sqrt(J2)) plane, where the
/// elastic stiffnesses are K and G and the deviator keeps its direction (de Souza Neto et al. 2008, Sec. 8.3).
#include <limits>
#include <string>

#include "mpm/materials/frictional.hpp"

namespace mpm {

/// Which Mohr-Coulomb pyramid the cone goes through (de Souza Neto et al. 2008, Sec. 6.4): its outer edges
/// (triaxial compression), its inner edges (triaxial extension), or the plane-strain collapse stress.
enum class ConeMatch { outer, inner, plane_strain };

/// The cone's coefficients for friction angle phi: f = sqrt(J2) + eta p - xi c (the same formula with the
/// dilatancy angle gives eta_bar).
struct ConeCoefficients {
  Real eta, xi;
};
ConeCoefficients cone_coefficients(ConeMatch match, Real phi);

struct DruckerPrager : FrictionalSolid {
  ConeMatch match = ConeMatch::outer;
  /// t, the largest mean stress [Pa] (the tension cut-off); infinite: none, the cone's apex bounds p.
  Real tension = std::numeric_limits<Real>::infinity();
};

/// Check the material; throw InputError naming `where` and the key.
void validate(const DruckerPrager& m, const std::string& where);

/// Return a trial stress to the surface of the strength at plastic strain e: the cone, the cut-off, their
/// corner or the apex, whichever holds the backward-Euler stress.
FrictionalReturn return_at_strength(const DruckerPrager& m, const Eigen::Matrix3d& trial, Real e);

/// One step from sigma_n and eps_bar_n with strain increment de and spin increment dW (de(2, 2) as given: plane
/// strain, the hoop strain or 3-D).
StressUpdate update_stress(const DruckerPrager& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                               const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW);

}  // namespace mpm

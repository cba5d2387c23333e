#pragma once
/// Mohr-Coulomb plasticity with non-associated flow and the multi-surface return in principal stresses of
/// de Souza Neto et al. 2008, Sec. 8.2: to the main plane, to the left or right edge, or to the apex.
///
/// With ordered principal stresses s1 >= s2 >= s3 (tension positive) the yield function is
/// f = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi) and the plastic potential g = (s1 - s3) + (s1 + s3)
/// sin(psi); the edges add the plane of (s1, s2) or of (s2, s3). Elasticity being isotropic, the principal
/// directions of the trial stress are kept.
#include <string>

#include "mpm/materials/frictional.hpp"

namespace mpm {

struct MohrCoulomb : FrictionalSolid {};

/// Check the material; throw InputError naming `where` and the key.
void validate(const MohrCoulomb& m, const std::string& where);

/// Return a trial stress to the surface of the strength at plastic strain e.
FrictionalReturn return_at_strength(const MohrCoulomb& m, const Eigen::Matrix3d& trial, Real e);

/// One step from sigma_n and eps_bar_n with strain increment de and spin increment dW (de(2, 2) as given:
/// plane strain, the hoop strain or 3-D).
StressUpdate update_stress(const MohrCoulomb& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                           const Eigen::Matrix3d& de, const Eigen::Matrix3d& dW);

}  // namespace mpm

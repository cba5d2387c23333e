#pragma once
/// Modified Cam-Clay: the critical-state model of Roscoe & Burland 1968 for clays, with the elliptical yield
/// surface f = q^2 / M^2 + p' (p' - p_c) (p' = -tr(sigma) / 3 > 0 in compression, q = sqrt(3 J2)), associated
/// flow, and hardening of the preconsolidation pressure p_c with the plastic volume change.
///
/// The volumetric laws are those of Butterfield 1979, linear in ln v against ln p' (v the specific volume, so
/// d ln v = -d eps_v with eps_v the logarithmic volumetric strain, compression positive): an elastic swelling
/// line of slope kappa* and a normal compression line of slope lambda*, integrated exactly over a step (the
/// exponential forms of Borja & Tamagnini 1998):
///   p' = p'_n exp(d eps_v^e / kappa*),     p_c = p_c,n exp(d eps_v^p / (lambda* - kappa*)).
/// Over any path, then, eps_v = kappa* ln(p' / p'_0) + (lambda* - kappa*) ln(p_c / p_c,0) holds to round-off,
/// which is what the tests assert. The shear modulus is given, or follows from a constant Poisson ratio and
/// the bulk modulus K = p'_n / kappa* at the start of the step. The step is the hypoelastic trial of the
/// rate-form laws (the stress rotated by the Jaumann rate, Sulsky & Kaul 2004, Sec. 2.2.4) returned to the
/// surface by backward Euler in the invariants p' and q (Borja & Lee 1990).
///
/// Stresses are Cauchy stresses, tension positive, as everywhere in this code; p' here is compression
/// positive, as in the soil-mechanics literature.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/elastoplastic.hpp"
#include "mpm/materials/parameters.hpp"
#include "mpm/materials/state.hpp"

namespace mpm {

struct ModifiedCamClay {
  static constexpr const char* model = "modified-cam-clay";
  Real rho0 = 0;         ///< reference density [kg/m^3]
  Real M = 0;            ///< slope of the critical state line, q = M p'
  Real lambda_star = 0;  ///< slope of the normal compression line in ln v against ln p' (lambda / v)
  Real kappa_star = 0;   ///< slope of the swelling line in ln v against ln p' (kappa / v)
  Real nu =
      std::numeric_limits<Real>::quiet_NaN();  ///< constant Poisson ratio (G from K), or NaN when G is given
  Real G = std::numeric_limits<Real>::quiet_NaN();  ///< constant shear modulus [Pa], or NaN when nu is given
  Real pc0 = 0;  ///< initial preconsolidation pressure p_c,0 [Pa] (> 0, compression positive)

  /// Its keys in a [[materials]] table (with density and model).
  static constexpr auto parameters() {
    constexpr Real none = std::numeric_limits<Real>::quiet_NaN();
    using P = Parameter<ModifiedCamClay>;
    return std::array{P{"M", &ModifiedCamClay::M, true, 0, "the slope of the critical state line q = M p'"},
                      P{"compression_index", &ModifiedCamClay::lambda_star, true, 0,
                        "lambda*, the slope of the normal compression line in ln v against ln p'"},
                      P{"swelling_index", &ModifiedCamClay::kappa_star, true, 0,
                        "kappa*, the slope of the swelling line in ln v against ln p'"},
                      P{"nu", &ModifiedCamClay::nu, false, none, "a constant Poisson ratio"},
                      P{"shear_modulus", &ModifiedCamClay::G, false, none, "a constant shear modulus [Pa]"},
                      P{"preconsolidation_pressure", &ModifiedCamClay::pc0, true, 0,
                        "the initial preconsolidation pressure p_c [Pa], compression positive"}};
  }

  /// Its internal variable: the preconsolidation pressure p_c [Pa].
  static constexpr std::array<StateColumn, 1> state_columns{{{"preconsolidation_pressure", "Pa"}}};
  /// p_c,0 at a particle of stress sigma: `given`'s where it is a number (a particle file's), else the
  /// material's; throws InputError unless p_c,0 > 0 and sigma lies in compression inside the initial yield
  /// surface (p' > 0, f <= 0: the model has no tensile strength).
  InternalState initial_state(const SymTensor<3>& sigma, const InternalState& given) const;

  Real bulk_at(Real p) const { return p / kappa_star; }  ///< K = p' / kappa* [Pa]
  Real shear_at(Real p) const {                          ///< G [Pa], given or from nu and K(p')
    return std::isnan(G) ? 3 * bulk_at(p) * (1 - 2 * nu) / (2 * (1 + nu)) : G;
  }
  /// Dilatational wave speed sqrt((K + 4 G / 3) / rho) at the stress sigma and volume ratio J [m/s].
  Real wave_speed(Real J, const SymTensor<3>& sigma) const {
    const Real p = std::max<Real>(0, -(sigma(0, 0) + sigma(1, 1) + sigma(2, 2)) / 3);
    return std::sqrt((bulk_at(p) + 4 * shear_at(p) / 3) * J / rho0);
  }
  /// The small-strain moduli at its reference state, an isotropic stress of p_c,0 (the implicit residual's
  /// scale, absorbing faces, estimates before a run).
  Real reference_lambda() const { return bulk_at(pc0) - 2 * shear_at(pc0) / 3; }
  Real reference_mu() const { return shear_at(pc0); }
};

/// Check the material in a geometry; throw InputError naming `where` and the key.
void validate(const ModifiedCamClay& m, const std::string& where, Geometry geometry);

/// One step from sigma_n, eps_bar_n and p_c (internal_n) with strain increment de and spin increment dW
/// (de(2, 2) as given: plane strain, the hoop strain or 3-D). eps_bar accumulates the deviatoric plastic
/// strain d eps_q^p = dgamma 2 q / M^2; the result's `internal` holds the new p_c. Throws SimulationFailure
/// when the mean effective stress at the start is not positive or the return does not converge.
StressUpdate update_stress(const ModifiedCamClay& m, const Eigen::Matrix3d& sigma_n, Real eps_bar_n,
                           const InternalState& internal_n, const Eigen::Matrix3d& de,
                           const Eigen::Matrix3d& dW);

}  // namespace mpm

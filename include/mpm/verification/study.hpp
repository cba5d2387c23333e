#pragma once
/// Running a manufactured-solution case and measuring its error.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/explicit/spec.hpp"
#include "mpm/verification/error_norms.hpp"

namespace mpm {

/// The built-in manufactured solutions.
enum class VerifyCase {
  axis_aligned,    ///< 2-D axis-aligned displacement in the unit square (Wallstedt & Guilkey 2008, Sec. 5.1)
  bar_1d,          ///< 1-D fixed-fixed bar, u = A sin(2 pi X/L) cos(c pi t/L)
  expanding_ring,  ///< 2-D expanding ring (Wallstedt & Guilkey 2008, Sec. 5.2), quarter model
  shear_wave,  ///< 2-D standing shear wave along the diagonal of the periodic unit square (shear_wave.hpp)
};
VerifyCase parse_case(std::string_view name);  ///< throws InputError naming the expected cases
std::string_view to_string(VerifyCase c);

/// The wave speed of the CFL condition.
enum class CflSpeed {
  particles,  ///< dt = cfl h / max_p(c_p + |v_p|) every step, c_p the dilatational speed at the particle's J
  reference,  ///< dt = cfl h / c, fixed, c^2 = E / rho0 the solution's wave speed (Wallstedt & Guilkey 2008,
              ///< Sec. 5)
};
/// Where the error is measured.
enum class ErrorMeasure {
  particles,  ///< displacement at the particles (Wallstedt & Guilkey 2008, Eq. (64))
  nodal,      ///< acceleration at the nodes (Wallstedt & Guilkey 2008, Eq. (A.1), Eq. (A.2))
};
/// How centered difference and UVF-MPM start.
enum class HalfStepStart {
  halve,  ///< from v^0, halving the first grid acceleration (the paper's choice for all its runs)
  exact,  ///< from the exact v^{-1/2} = v(X, -dt/2) (Wallstedt & Guilkey 2008, Sec. 4); needs a fixed dt
};

struct VerifyOptions {
  int dim = 0;  ///< 0: the case's own (axis-aligned: 2, or 3 when asked)
  KernelKind kernel = KernelKind::cpgimp;
  Transfer transfer = Transfer::flip;  ///< the particle velocity update: FLIP, or APIC (Jiang et al. 2015)
  Integrator integrator = Integrator::cd;  ///< the explicit integrator, unless `implicit`
  /// The implicit integrator of Sulsky & Kaul 2004: theta-blended steps of the explicit
  /// CFL step, solved by Newton-GMRES to a residual of 1e-10 (linear tolerance 1e-6), far below the errors.
  bool implicit = false;
  Real theta = 1;  ///< the implicit blend: 1 backward Euler, 0.5 the midpoint rule
  int cells = 32;  ///< cells per axis across the body's reference extent
  int ppc = 2;     ///< particles per cell per axis
  Real cfl = 0.4;  ///< the CFL number of `cfl_speed`
  CflSpeed cfl_speed = CflSpeed::particles;
  ErrorMeasure error = ErrorMeasure::particles;
  HalfStepStart start = HalfStepStart::halve;
  /// Acceleration on the constrained nodes of the symmetry planes: zero, or Steffen et al. 2008, Eq. (30).
  ConstrainedAcceleration constrained_acceleration = ConstrainedAcceleration::zero;
  Real amplitude = 0.1;  ///< A of the manufactured displacement [m]
  /// Poisson's ratio of the axis-aligned case (which Wallstedt & Guilkey 2008 do not state); unset: the
  /// case's own, 0.3 for the axis-aligned case and 0 for the bar and the ring, whose closed forms need it.
  std::optional<Real> poisson;
  Real end_time = 0;  ///< 0: one period of the motion
};

/// "implicit", or the explicit integrator's name.
std::string_view integrator_name(const VerifyOptions& o);
/// Set the integrator from a name: an explicit one, or "implicit"; throws InputError naming `key`.
void set_integrator(VerifyOptions& o, std::string_view name, std::string_view key);

/// Poisson's ratio the case runs with.
Real poisson_ratio(VerifyCase c, const VerifyOptions& o);

/// The dimension a case runs in with these options.
int dimension(VerifyCase c, const VerifyOptions& o);

struct VerifyResult {
  bool ok = true;
  std::string failure;  ///< the SimulationFailure message when !ok
  std::int64_t steps = 0;
  Real end_time = 0;
  ErrorNorms error;  ///< L_inf = 1 for plotting when the run failed (Wallstedt & Guilkey 2008, Sec. 6.1.1)
  Real dt = 0;       ///< the first step's time step [s]
};

/// Final particle states as a table: reference and current positions, velocity, J, stress components and
/// the displacement error of Wallstedt & Guilkey 2008, Eq. (64), one row per particle.
struct ParticleTable {
  std::vector<std::string> columns;
  std::vector<std::vector<Real>> rows;
};

/// Run a case from its exact state at t = 0 (E = 1e7 Pa, nu = 0.3 for axis-aligned and 0 for the bar and
/// ring, rho0 = 1000 kg/m^3, symmetry planes where the displacement is odd), recording the error after every
/// step. When `final_state` is given it receives the particles at the end (also after a failure).
VerifyResult verify(VerifyCase c, const VerifyOptions& o, ParticleTable* final_state = nullptr);

/// Throw InputError for impossible options (cells < 2, ppc < 1, cfl outside (0, 1] or with the reference
/// speed (0, 2], amplitude, end time, theta outside [0, 1], a nodal error or an exact start the integrator
/// lacks).
void validate(const VerifyOptions& o);

}  // namespace mpm

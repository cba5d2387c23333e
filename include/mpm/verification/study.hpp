#pragma once
/// Running a manufactured-solution case and measuring its error.
#include <functional>
#include <string>

#include "mpm/integrators/spec.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/verification/error_norms.hpp"

namespace mpm {

struct VerifyOptions {
  KernelKind kernel = KernelKind::cpgimp;
  Integrator integrator = Integrator::cd;
  int cells = 32;          ///< cells per axis across the body's reference extent
  int ppc = 2;             ///< particles per cell per axis
  Real cfl = 0.4;          ///< dt = cfl h / max_p(c_p + |v_p|)
  Real amplitude = 0.1;    ///< A of the manufactured displacement [m]
  Real end_time = 0;       ///< 0: one period of the motion
};

struct VerifyResult {
  bool ok = true;
  std::string failure;  ///< the SimulationFailure message when !ok
  std::int64_t steps = 0;
  Real end_time = 0;
  ErrorNorms error;     ///< L_inf = 1 for plotting when the run failed (Wallstedt & Guilkey 2008, Sec. 6.1.1)
};

/// The 2-D axis-aligned displacement case in the unit square (Wallstedt & Guilkey 2008, Sec. 5.1) with
/// symmetry planes on all four faces, E = 1e7 Pa, nu = 0.3, rho0 = 1000 kg/m^3. `on_finish` sees the final
/// particles (also after a failure).
VerifyResult verify_axis_aligned(const VerifyOptions& o,
                                 const std::function<void(const ParticleSet<2>&)>& on_finish = {});

/// Throw InputError for impossible options (cells < 2, ppc < 1, cfl outside (0, 1], amplitude, end time).
void validate(const VerifyOptions& o);

}  // namespace mpm

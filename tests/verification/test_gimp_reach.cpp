// How far each GIMP stencil lets a particle grow: a bar expanding freely at unit strain rate, F = 1 + t, with
// 2 particles per cell (l_p0 = h/4). cpGIMP's half-lengths l_p0 F pass h/2 at t = 1; the wide stencil
// (cpgimp-wide, WideGimpKernel) holds them up to h, until t = 3; CPDI scales a domain past one cell about its
// centre and runs on. Each stop names the kernel that goes further.
#include <gtest/gtest.h>

#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {
namespace {

struct Expansion {
  Real time = 0;
  std::string failure;
  Real stretch = 0;  ///< the largest F of the run's last state
};

/// A 1-D bar [4.5, 5.5] on a grid [0, 10] of h = 0.1, v = x - 5, a material soft enough (E = 1e-6 Pa against
/// a kinetic energy density of order 0.1) that the bar expands as if free, USL to t = 5.
Expansion expand(KernelKind kind) {
  SimulationSpec<1> spec;
  spec.h = 0.1;
  spec.cells = {100};
  spec.kernel = kind;
  spec.integrator = Integrator::usl;
  spec.materials = {NeoHookean::from_young_poisson(1e-6, 0, 1)};
  spec.cfl = 0.4;
  ParticleSet<1> p;
  fill_box<1>(p, Vec<1>(4.5), Vec<1>(5.5), spec.h / 2, 1.0, 0);
  for (std::size_t i = 0; i < p.size(); ++i) p.v[i] = Vec<1>(p.x[i][0] - 5);
  Expansion e;
  with_kernel<1>(kind, [&]<class K>() {
    Simulation<1, K> sim(spec, std::move(p));
    try {
      sim.run_until(5);
    } catch (const SimulationFailure& f) {
      e.failure = f.what();
    }
    e.time = sim.time();
    for (const Mat<1>& F : sim.particles().F) e.stretch = std::max(e.stretch, F(0, 0));
  });
  return e;
}

/// A run that stopped in the step past time `at` (F = 1 + t), its message naming `bound`, with the stretch of
/// the state the failed step left just past 1 + at.
void expect_stopped(const Expansion& e, Real at, const std::string& bound) {
  EXPECT_NE(e.failure.find(bound), std::string::npos) << e.failure;
  EXPECT_GT(e.time, at - 0.1);
  EXPECT_LT(e.time, at);
  EXPECT_GT(e.stretch, 1 + at);
  EXPECT_LT(e.stretch, 1.1 + at);
}

TEST(GimpReach, EachStencilHoldsTheHalfLengthsItPromises) {
  // Measured: cpgimp stops in the step to t = 1.0084 (F = 2.020 > 2), cpgimp-wide in the step to t = 3.0253
  // (F = 4.065 > 4), CPDI reaches t = 5 with F = 5.9987 (its domains scaled to one cell from F = 4 on).
  // The message names the kinds that go further: the wide stencil, CPDI, and uGIMP's fixed half-lengths.
  expect_stopped(
      expand(KernelKind::cpgimp), 1,
      "left (0, h/2] (kernel = \"cpgimp-wide\" takes half-lengths up to h, kernel = \"cpdi\" follows "
      "any deformation, kernel = \"ugimp\" keeps each particle's initial half-lengths)");
  expect_stopped(expand(KernelKind::cpgimp_wide), 3,
                 "left (0, h] (kernel = \"cpdi\" follows any deformation, kernel = \"ugimp-wide\" keeps each "
                 "particle's initial half-lengths)");
  const Expansion cpdi = expand(KernelKind::cpdi);
  EXPECT_TRUE(cpdi.failure.empty()) << cpdi.failure;
  EXPECT_NEAR(cpdi.time, 5, 1e-12);
  EXPECT_NEAR(cpdi.stretch, 6, 0.01);
}

}  // namespace
}  // namespace mpm

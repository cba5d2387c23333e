// How far each GIMP stencil lets a particle grow: a bar expanding freely at unit strain rate, F = 1 + t, with
// 2 particles per cell (l_p0 = h/4). cpGIMP's half-lengths l_p0 F pass h/2 at t = 1; the wide stencil
// (cpgimp-wide, WideGimpKernel) holds them up to h, until t = 3; from there on each stencil bounds them to
// its reach (ParticleSet's deformed_half_length) and the run goes on, as CPDI's, which scales a domain past
// one cell about its centre.
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
  Real stretch = 0;         ///< the largest F of the run's last state
  Real first_bounded = -1;  ///< the end of the first step after which a particle's half-length was bounded
  Real largest_half = 0;    ///< the largest half-length of the last state
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
      while (sim.time() < 5 * (1 - 1e-14)) {
        sim.step(5 - sim.time());
        for (std::size_t i = 0; i < sim.particles().size() && e.first_bounded < 0; ++i)
          if (sim.particles().half_length_bounded(i)) e.first_bounded = sim.time();
      }
    } catch (const SimulationFailure& f) {
      e.failure = f.what();
    }
    e.time = sim.time();
    const ParticleSet<1>& q = sim.particles();
    for (std::size_t i = 0; i < q.size(); ++i) {
      e.stretch = std::max(e.stretch, q.F[i](0, 0));
      e.largest_half = std::max(e.largest_half, q.half_length(i)[0]);
    }
  });
  return e;
}

/// A run that reached t = 5, whose half-lengths were first bounded in the step past time `at` (F = 1 + t,
/// l_p0 F past the bound), that went on stretching (F more than one above 1 + at, and no more than the free
/// bar's 6), and whose largest half-length is then `bound` [m].
void expect_bounded(const Expansion& e, Real at, Real bound) {
  EXPECT_TRUE(e.failure.empty()) << e.failure;
  EXPECT_NEAR(e.time, 5, 1e-12);
  EXPECT_GT(e.first_bounded, at);
  EXPECT_LT(e.first_bounded, at + 0.1);
  EXPECT_GT(e.stretch, 2 + at);
  EXPECT_LT(e.stretch, 6.01);
  EXPECT_EQ(e.largest_half, bound);
}

TEST(GimpReach, EachStencilBoundsTheHalfLengthsPastItsReachAndRunsOn) {
  // Measured: cpgimp's half-lengths are first bounded after the step to t = 1.0084 (F = 2.020 > 2), where the
  // run used to stop; cpgimp-wide's after the step to t = 3.0253 (F = 4.065 > 4). Both reach t = 5, with a
  // largest F of 4.875 and 5.717 against the free bar's 6: bounded domains no longer fill the bar, whose
  // particles then move with node velocities averaged over fewer neighbours. CPDI reaches t = 5 with F
  // = 5.9987 (its domains scaled to one cell from F = 4 on).
  expect_bounded(expand(KernelKind::cpgimp), 1, 0.05);
  expect_bounded(expand(KernelKind::cpgimp_wide), 3, 0.1);
  const Expansion cpdi = expand(KernelKind::cpdi);
  EXPECT_TRUE(cpdi.failure.empty()) << cpdi.failure;
  EXPECT_NEAR(cpdi.time, 5, 1e-12);
  EXPECT_NEAR(cpdi.stretch, 6, 0.01);
}

}  // namespace
}  // namespace mpm

// The start of the centered-difference step (Wallstedt & Guilkey 2008, Sec. 4): from v^0 with the first grid
// acceleration halved, or from given half-step velocities v^{-1/2}.
#include <gtest/gtest.h>

#include <cmath>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {
namespace {

constexpr Real g = -9.81, dt = 1e-3, v0 = 0.4;

/// A stress-free block thrown upwards at v0 under gravity g in a large grid of free faces: every particle
/// and node has the same velocity, the velocity gradient is zero, so the motion is x = x0 + v0 t + g t^2 / 2.
Simulation<2, LinearKernel> thrown_block(Integrator integrator, bool half_step_velocity_given, Real v_start) {
  SimulationSpec<2> spec;
  spec.h = 0.1;
  spec.cells = {20, 20};
  spec.integrator = integrator;
  spec.materials = {NeoHookean::from_young_poisson(1e5, 0.3, 1000)};
  spec.gravity = Vec<2>(0, g);
  spec.dt = dt;
  spec.half_step_velocity_given = half_step_velocity_given;
  ParticleSet<2> p;
  fill_box<2>(p, Vec<2>(0.8, 0.8), Vec<2>(1.2, 1.2), spec.h / 2, 1000, 0,
              [&](const Vec<2>&) { return Vec<2>(0, v_start); });
  return {spec, std::move(p)};
}

/// The largest |y_p - y_exact| and |v_p - v_expected| over the particles.
std::pair<Real, Real> deviation(const Simulation<2, LinearKernel>& sim, Real y_exact_shift, Real v_expected) {
  const ParticleSet<2>& p = sim.particles();
  Real dy = 0, dv = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    dy = std::max(dy, std::abs(p.x[i][1] - (p.X[i][1] + y_exact_shift)));
    dv = std::max(dv, std::abs(p.v[i][1] - v_expected));
  }
  return {dy, dv};
}

TEST(CenteredDifference, HalvedFirstAccelerationTurnsV0IntoTheHalfStepVelocity) {
  // Wallstedt & Guilkey 2008, Sec. 4: halving the first grid acceleration gives v^{1/2} = v^0 + a dt / 2, and
  // x^1 = x^0 + v^{1/2} dt is the exact position under constant acceleration. USL takes the whole a dt.
  auto cd = thrown_block(Integrator::cd, false, v0);
  cd.step();
  const auto [dy_cd, dv_cd] = deviation(cd, v0 * dt + g * dt * dt / 2, v0 + g * dt / 2);
  EXPECT_LT(dy_cd, 1e-15);  // round-off of the sums of weights (Sum_i S_ip = 1)
  EXPECT_LT(dv_cd, 1e-14);
  auto usl = thrown_block(Integrator::usl, false, v0);
  usl.step();
  const auto [dy_usl, dv_usl] = deviation(usl, v0 * dt + g * dt * dt, v0 + g * dt);
  EXPECT_LT(dy_usl, 1e-15);
  EXPECT_LT(dv_usl, 1e-14);
}

TEST(CenteredDifference, ExactHalfStepStartAndHalvedStartFollowTheSameParabola) {
  // Given v^{-1/2} = v0 - g dt / 2 the first acceleration is not halved; both starts then stay on the exact
  // parabola for every step (centered difference integrates constant acceleration exactly), while USL lags by
  // g dt t / 2, first order in dt.
  const int steps = 50;
  const Real t = steps * dt;
  auto halved = thrown_block(Integrator::cd, false, v0);
  auto given = thrown_block(Integrator::cd, true, v0 - g * dt / 2);
  auto usl = thrown_block(Integrator::usl, false, v0);
  for (int n = 0; n < steps; ++n) {
    halved.step();
    given.step();
    usl.step();
  }
  const Real shift = v0 * t + g * t * t / 2;
  EXPECT_LT(deviation(halved, shift, v0 + g * (t - dt / 2)).first, 1e-13);
  EXPECT_LT(deviation(given, shift, v0 + g * (t - dt / 2)).first, 1e-13);
  EXPECT_LT(deviation(given, shift, v0 + g * (t - dt / 2)).second, 1e-12);
  // USL: x_n = x0 + v0 t + g dt^2 n(n+1)/2, i.e. g dt t / 2 above the parabola (g < 0: below it).
  EXPECT_NEAR(deviation(usl, shift, 0).first, std::abs(g) * dt * t / 2, 1e-12);
}

TEST(CenteredDifference, HalfStepVelocitiesAreRefusedForIntegratorsWithoutAHalfStep) {
  for (Integrator i : {Integrator::usf, Integrator::usl}) {
    try {
      thrown_block(i, true, v0);
      ADD_FAILURE() << "accepted half-step velocities for " << to_string(i);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("half_step_velocity_given"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mpm

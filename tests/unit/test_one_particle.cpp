// The one-particle system of Wallstedt & Guilkey 2008, Sec. 3 (Fig. 1): one 1-D cell [0, h], the left node
// fixed, the right node free, linear shape functions, one particle. One step of the real
// Simulation<1, LinearKernel> must reproduce the closed forms (34)-(36) for USF and (37)-(39) for USL.
//
// Sign of the force. Eq. (14) is f_i = -sum_p grad S_ip . sigma_p V_p. For the right node grad S_ip = +1/h
// and sigma_p V_p = (E/2)(F - 1/F) F V_p^0 = (E/2)(F^2 - 1) V_p^0 (Eq. 28 and V_p = F V_p^0 in 1-D), so
//     f_i = -(E/(2h)) (F^2 - 1) V_p^0,
// i.e. a particle in tension (F > 1) pulls the free right node back toward the fixed one. Eqs (27), (29)-(35)
// and (37)-(39) as printed have the opposite sign (Eq. (27) drops the minus of Eq. (14)): a bar in tension
// would be pushed further apart. The closed forms below therefore take the sign that follows from Eq. (14)
// (a minus in front of the E/(2h) terms of Eqs (34), (35), (37), (38) and the E/2 term of Eq. (39)), and the
// test PrintedSignIsOpposite documents that the equations as printed do not match the library.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mpm/explicit/simulation.hpp"

namespace {

using mpm::Real;

// Material and particle constants shared by every sample (arbitrary, chosen so that m_p / V_p^0 != rho0).
constexpr Real kE = 100.0;   // Young's modulus
constexpr Real kM = 1.3;     // particle mass m_p
constexpr Real kV0 = 0.9;    // particle reference volume V_p^0
constexpr Real kRho0 = 1.0;  // reference density (only used for the CFL speed, unused with a fixed dt)

// One sample of the time-n state (x_p, v_p, F_p), the cell width and the time step.
struct Sample {
  Real h, x, v, F, dt;
};

struct State {
  Real x, v, F;
};

// Single-step errors are a few ulps of the largest term of each closed form; 1e-13 leaves ~500 ulps of
// margin.
constexpr Real kRelTol = 1e-13;

const std::vector<Sample> kSamples = {
    {1.0, 0.30, 0.20, 1.10, 1e-3},   // tension, moving right
    {2.0, 1.50, -0.50, 0.90, 2e-3},  // compression, moving left
    {0.5, 0.25, 0.00, 1.25, 5e-3},   // tension at rest
    {1.0, 0.90, 1.00, 1.00, 1e-3},   // stress-free at time n
    {3.0, 0.40, -0.30, 0.70, 4e-3},  // strong compression near the fixed node
};

// Run one step of the library on the one-particle system of Fig. 1.
State simulate(const Sample& s, mpm::Integrator integrator) {
  mpm::SimulationSpec<1> spec;
  spec.grid_lo = mpm::Vec<1>(0.0);
  spec.h = s.h;
  spec.cells = {1};
  spec.integrator = integrator;
  spec.kernel = mpm::KernelKind::linear;
  // Zero Poisson ratio: lambda = 0, mu = E/2, so sigma = (E/2)(F - 1/F) (Eq. 28).
  spec.materials = {mpm::NeoHookean::from_young_poisson(kE, 0.0, kRho0)};
  spec.boundary.faces[0] = {mpm::FaceType::velocity, {}};  // fixed left node (empty fn = zero velocity)
  spec.boundary.faces[1] = {mpm::FaceType::free, {}};
  spec.boundary.acceleration = mpm::ConstrainedAcceleration::zero;
  spec.dt = s.dt;

  mpm::ParticleSet<1> p;
  p.add(mpm::Vec<1>(s.x), mpm::Vec<1>(s.v), kM, kV0, mpm::Vec<1>(0.25 * s.h), 0);
  p.F[0](0, 0) = s.F;  // the constructor recomputes V = V0 det F and sigma(F)

  mpm::Simulation<1, mpm::LinearKernel> sim(spec, std::move(p));
  sim.step();
  const mpm::ParticleSet<1>& q = sim.particles();
  return {q.x[0][0], q.v[0][0], q.F[0](0, 0)};
}

// A closed form written as the sum of its terms, so that the tolerance can be relative to the terms'
// magnitudes (the round-off of a sum is bounded relative to the sum of the absolute values of its terms).
struct Terms {
  Real value = 0, magnitude = 0;
  Terms& operator+=(Real t) {
    value += t;
    magnitude += std::abs(t);
    return *this;
  }
};

struct Expected {
  Terms x, v, F;
};

// USF closed forms, sign of the force from Eq. (14). `force_sign` = -1 follows Eq. (14); +1 is the printed
// form.
Expected usf_closed_form(const Sample& s, Real force_sign) {
  const Real F1 = (1 + s.v / s.h * s.dt) * s.F;  // Wallstedt & Guilkey 2008, Eq. (36)
  const Real K = force_sign * kE / (2 * s.h) * (F1 * F1 - 1) * (kV0 / kM);
  Expected e;
  e.x += s.x;  // Eq. (34)
  e.x += s.v * (s.x / s.h) * s.dt;
  e.x += K * s.dt * s.dt;
  e.v += s.v;  // Eq. (35)
  e.v += K * s.dt;
  e.F += F1;
  return e;
}

// USL closed forms, sign of the force from Eq. (14) for force_sign = -1.
Expected usl_closed_form(const Sample& s, Real force_sign) {
  const Real K = force_sign * kE / (2 * s.h) * (s.F * s.F - 1) * (kV0 / kM);
  Expected e;
  e.x += s.x;  // Wallstedt & Guilkey 2008, Eq. (37)
  e.x += s.v * (s.x / s.h) * s.dt;
  e.x += K * s.dt * s.dt;
  e.v += s.v;  // Eq. (38)
  e.v += K * s.dt;
  // Eq. (39): F^{n+1} = (1 + (v/h + force_sign (E/2)(F^2 - 1) V0 dt / (m x h)) dt) F.
  const Real grad_v = s.v / s.h + force_sign * kE / 2 * (s.F * s.F - 1) * kV0 * s.dt / (kM * s.x * s.h);
  e.F += s.F;
  e.F += grad_v * s.dt * s.F;
  return e;
}

void expect_matches(const State& got, const Expected& e, const Sample& s) {
  SCOPED_TRACE(::testing::Message() << "h=" << s.h << " x=" << s.x << " v=" << s.v << " F=" << s.F
                                    << " dt=" << s.dt);
  EXPECT_NEAR(got.x, e.x.value, kRelTol * e.x.magnitude);
  EXPECT_NEAR(got.v, e.v.value, kRelTol * e.v.magnitude);
  EXPECT_NEAR(got.F, e.F.value, kRelTol * e.F.magnitude);
}

TEST(OneParticle, UsfMatchesClosedForm) {
  for (const Sample& s : kSamples)
    expect_matches(simulate(s, mpm::Integrator::usf), usf_closed_form(s, -1), s);
}

TEST(OneParticle, UslMatchesClosedForm) {
  for (const Sample& s : kSamples)
    expect_matches(simulate(s, mpm::Integrator::usl), usl_closed_form(s, -1), s);
}

// A particle in tension (F > 1) must decelerate the free node, and the velocity change is the negative of the
// one printed in Eqs (35) and (38): the printed sign contradicts Eq. (14).
TEST(OneParticle, PrintedSignIsOpposite) {
  const Sample s = kSamples[0];
  ASSERT_GT(s.F, 1.0);
  struct Case {
    mpm::Integrator integrator;
    Expected (*closed_form)(const Sample&, Real);
  };
  for (const Case& c :
       {Case{mpm::Integrator::usf, usf_closed_form}, Case{mpm::Integrator::usl, usl_closed_form}}) {
    const State got = simulate(s, c.integrator);
    const Expected printed = c.closed_form(s, +1);
    const Real dv = got.v - s.v;
    const Real dv_printed = printed.v.value - s.v;
    EXPECT_LT(dv, 0.0);          // tension pulls the free node back toward the fixed node
    EXPECT_GT(dv_printed, 0.0);  // ... while the printed equations push it away
    // Same magnitude, opposite sign (to the round-off of v^n + dv, as in expect_matches) ...
    EXPECT_NEAR(dv, -dv_printed, kRelTol * (std::abs(s.v) + std::abs(dv)));
    // ... so the printed Eq. (35)/(38) misses the library by 2|dv| ~ 1.5e-2, ten orders above the tolerance.
    EXPECT_GT(std::abs(got.v - printed.v.value), 1e9 * kRelTol * (std::abs(s.v) + std::abs(dv)));
  }
}

}  // namespace

// Light nodes (SimulationSpec::reproject_light_nodes): a node that a particle barely reaches gets, with the
// linear kernel, an acceleration f_i / m_i ~ 1 / S_ip whose gradient term blows up (Wallstedt & Guilkey 2008,
// Eq. (39)). USL and CD then move and deform the particles with the velocity re-projected from the updated
// particle velocities at such nodes (Sulsky & Kaul 2004, Eq. (3.2.7)). Checked on two particles worked by
// hand and on a fixed-free vibrating bar whose free end crosses cell faces, for every kernel and explicit
// integrator.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/generate.hpp"

namespace {

using mpm::Real;
using mpm::Vec;

// ---------------------------------------------------------------------------------------------------------------
// Two particles, one step of USL, against the step written out here from the equations.

struct Particle {
  Real x, v, F;
};

constexpr Real kE = 100, kH = 1, kDt = 1e-3, kMass = 1, kV0 = 1;

// Linear hat weight and gradient of node i at x (h = 1).
Real hat(int i, Real x) {
  return std::max(0.0, 1 - std::abs(x - i));
}
Real hat_gradient(int i, Real x) {
  return std::abs(x - i) < 1 ? (x < i ? 1.0 : -1.0) / kH : 0.0;
}

/// One USL step (Wallstedt & Guilkey 2008, Eqs 8-9, 14-19) on nodes 0..3; with `reproject`, nodes lighter
/// than a quarter particle move and deform the particles with the re-projected velocity.
std::vector<Particle> usl_by_hand(std::vector<Particle> p, bool reproject) {
  constexpr int nodes = 4;
  Real m[nodes] = {}, mv[nodes] = {}, f[nodes] = {};
  for (const Particle& q : p) {
    const Real sigma = 0.5 * kE * (q.F - 1 / q.F);  // lambda = 0: sigma = mu (F^2 - 1) / J with J = F
    for (int i = 0; i < nodes; ++i) {
      m[i] += kMass * hat(i, q.x);
      mv[i] += kMass * q.v * hat(i, q.x);
      f[i] -= kV0 * q.F * sigma * hat_gradient(i, q.x);
    }
  }
  Real a[nodes] = {}, v_new[nodes] = {};
  for (int i = 0; i < nodes; ++i)
    if (m[i] > 0) a[i] = f[i] / m[i], v_new[i] = mv[i] / m[i] + kDt * a[i];
  for (Particle& q : p)
    for (int i = 0; i < nodes; ++i) q.v += kDt * hat(i, q.x) * a[i];
  if (reproject) {
    Real mv_new[nodes] = {};
    for (const Particle& q : p)
      for (int i = 0; i < nodes; ++i) mv_new[i] += kMass * q.v * hat(i, q.x);
    for (int i = 0; i < nodes; ++i)
      if (m[i] > 0 && m[i] < 0.25 * kMass) v_new[i] = mv_new[i] / m[i];
  }
  for (Particle& q : p) {
    Real dx = 0, L = 0;
    for (int i = 0; i < nodes; ++i) dx += kDt * hat(i, q.x) * v_new[i], L += v_new[i] * hat_gradient(i, q.x);
    q.x += dx;
    q.F *= 1 + kDt * L;
  }
  return p;
}

std::vector<Particle> usl_step(const std::vector<Particle>& start, bool reproject) {
  mpm::SimulationSpec<1> spec;
  spec.h = kH;
  spec.cells = {3};
  spec.integrator = mpm::Integrator::usl;
  spec.kernel = mpm::KernelKind::linear;
  spec.materials = {mpm::NeoHookean::from_young_poisson(kE, 0.0, 1.0)};
  spec.dt = kDt;
  spec.reproject_light_nodes = reproject;
  mpm::ParticleSet<1> p;
  for (const Particle& q : start) {
    p.add(Vec<1>(q.x), Vec<1>(q.v), kMass, kV0, Vec<1>(0.25), 0);
    p.F.back()(0, 0) = q.F;
  }
  mpm::Simulation<1, mpm::LinearKernel> sim(spec, std::move(p));
  sim.step();
  std::vector<Particle> out;
  for (std::size_t k = 0; k < start.size(); ++k)
    out.push_back({sim.particles().x[k][0], sim.particles().v[k][0], sim.particles().F[k](0, 0)});
  return out;
}

TEST(LightNodes, TwoParticleStepMatchesTheHandComputation) {
  // Particle b at x = 1.1 reaches node 2 with weight 0.1: m_2 = 0.1 m_p, a light node; node 0 gets 0.3 m_p
  // from particle a and nodes 1 gets 1.6 m_p. b is stretched (F = 1.2), so f_2 / m_2 is ten times f_2 / m_p.
  const std::vector<Particle> start = {{0.7, 0.2, 1.05}, {1.1, 0.5, 1.2}};
  for (bool reproject : {false, true}) {
    SCOPED_TRACE(reproject ? "re-projected light nodes" : "the paper's USL");
    const std::vector<Particle> got = usl_step(start, reproject), want = usl_by_hand(start, reproject);
    for (std::size_t k = 0; k < start.size(); ++k) {
      // One step: a few ulps of each term (measured <= 2e-16 relative); 1e-13 leaves margin.
      EXPECT_NEAR(got[k].x, want[k].x, 1e-13 * std::abs(want[k].x));
      EXPECT_NEAR(got[k].v, want[k].v, 1e-13);
      EXPECT_NEAR(got[k].F, want[k].F, 1e-13 * std::abs(want[k].F));
    }
    // Momentum: sum_i f_i = 0 and the velocities come from f_i / m_i either way, so it is kept to round-off.
    EXPECT_NEAR(got[0].v + got[1].v, start[0].v + start[1].v, 1e-15);
  }
}

TEST(LightNodes, ReprojectionBoundsTheStretchThatGrowsLikeOneOverTheWeight) {
  // Particle b at x = 1 + s reaches node 2 with weight s. At the CFL step of c = 10, h = 1 (dt = 0.05 would
  // invert b in one step without the treatment) the hand-worked step with dt = 1e-3 shows the growth: the
  // paper's change of F_b grows like 1 / s (Wallstedt & Guilkey 2008, Eq. (39)), the re-projected one stays
  // put.
  auto stretch = [](Real s, bool reproject) {
    const std::vector<Particle> start = {{0.7, 0.2, 1.05}, {1 + s, 0.5, 1.2}};
    return usl_by_hand(start, reproject)[1].F - start[1].F;
  };
  // dF ~ dt^2 F (f_2 / m_p) / s as s -> 0: ten times smaller s, ten times the change (within 2%;
  // measured 10.49 from s = 1e-2 to 1e-3, where the terms that do not grow still show).
  EXPECT_NEAR(stretch(1e-4, false) / stretch(1e-3, false), 10.0, 0.2);
  EXPECT_NEAR(stretch(1e-5, false) / stretch(1e-4, false), 10.0, 0.2);
  // Re-projected: the light node moves with particle b, bounded as s -> 0 (within 2% from s = 1e-2 to 1e-4).
  EXPECT_NEAR(stretch(1e-4, true) / stretch(1e-2, true), 1.0, 0.02);
  EXPECT_LT(std::abs(stretch(1e-4, true)), 1e-2 * std::abs(stretch(1e-4, false)));
}

// ---------------------------------------------------------------------------------------------------------------
// Fixed-free bar, u = (v0 / omega) sin(omega t) sin(pi X / 2L), omega = pi c / 2L (small strain). Its centre
// of mass moves at v_cm = (2 v0 / pi) cos(omega t). With v0 = 0.3 c / 10 the free end moves 0.019 L, more
// than a quarter cell (the end particle's distance to the cell face at 2 particles per cell) at 16, 32 and 64
// cells.

constexpr Real kL = 1, kC = 10, kV = 0.3;

struct BarResult {
  bool ran = false;
  Real max_error = 0;  ///< max over the steps of |v_cm - exact| / (2 v0 / pi)
  std::string failure;
};

template <class Kernel>
BarResult run_bar(mpm::KernelKind kind, mpm::Integrator integrator, int cells) {
  mpm::SimulationSpec<1> spec;
  spec.h = kL / cells;
  spec.cells = {2 * cells};  // the grid reaches twice the bar's length
  spec.integrator = integrator;
  spec.kernel = kind;
  spec.materials = {mpm::NeoHookean::from_young_poisson(kC * kC, 0.0, 1.0)};
  spec.cfl = 0.5;
  spec.reproject_light_nodes = true;
  spec.boundary.faces[0].type = mpm::FaceType::velocity;  // fixed end at X = 0
  mpm::ParticleSet<1> p;
  mpm::fill_box<1>(p, Vec<1>(0.0), Vec<1>(kL), spec.h / 2, 1.0, 0,
                   [](const Vec<1>& X) { return Vec<1>(kV * std::sin(std::numbers::pi * X[0] / (2 * kL))); });
  const Real omega = std::numbers::pi * kC / (2 * kL), amplitude = 2 * kV / std::numbers::pi;
  BarResult r;
  try {
    mpm::Simulation<1, Kernel> sim(spec, std::move(p));
    const Real periods = 3, end = periods * 2 * std::numbers::pi / omega;
    while (sim.time() < end * (1 - 1e-14)) {
      sim.step(end - sim.time());
      Real momentum = 0, mass = 0;
      for (std::size_t k = 0; k < sim.particles().size(); ++k)
        momentum += sim.particles().m[k] * sim.particles().v[k][0], mass += sim.particles().m[k];
      r.max_error = std::max(
          r.max_error, std::abs(momentum / mass - amplitude * std::cos(omega * sim.time())) / amplitude);
    }
    r.ran = true;
  } catch (const mpm::SimulationFailure& e) {
    r.failure = e.what();
  }
  return r;
}

BarResult run_bar(mpm::KernelKind kind, mpm::Integrator integrator, int cells) {
  return mpm::with_kernel<1>(kind, [&]<class Kernel>() { return run_bar<Kernel>(kind, integrator, cells); });
}

TEST(LightNodes, FixedFreeBarRunsToTheEndAndFollowsTheExactCentreOfMassVelocity) {
  // Max over 3 periods of |v_cm - exact| / (2 v0 / pi), measured at 16 / 32 / 64 cells along the bar:
  //   GIMP (ugimp, cpgimp):  USF 0.016 / 0.010 / 0.006, USL and CD 0.065 / 0.032 / 0.019, MUSL the same as
  //   USL B-splines (bspline2, bspline3): 0.35-0.55 / 0.16-0.27 / 0.08-0.14 for every integrator; first
  //   order, the
  //     error of the fixed end, whose ghost nodes the B-spline support reaches (seed 001); the clamped
  //     B-splines remove it (test_clamped_bsplines.cpp)
  //   linear: USL and CD 0.11 / 0.19 / 0.45, MUSL 0.12 / 0.24 / 0.68, USF 0.11 / 0.23 / 15.5: the
  //   grid-crossing
  //     error of the linear hat grows with refinement; at 64 cells USF's energy grows twelvefold in three
  //     periods, which no treatment of light nodes prevents (its gradients already use p_i / m_i), so USF
  //     with the linear kernel is checked at 16 and 32 cells only (docs/hardening.md).
  using K = mpm::KernelKind;
  using I = mpm::Integrator;
  for (K kernel : {K::linear, K::ugimp, K::cpgimp, K::bspline2, K::bspline3})
    for (I integrator : {I::usf, I::usl, I::cd, I::musl}) {
      Real errors[3];
      for (int level = 0; level < 3; ++level) {
        const int cells = 16 << level;
        SCOPED_TRACE(std::string(mpm::to_string(kernel)) + " " + std::string(mpm::to_string(integrator)) +
                     " " + std::to_string(cells) + " cells");
        const BarResult r = run_bar(kernel, integrator, cells);
        EXPECT_TRUE(r.ran) << r.failure;
        errors[level] = r.max_error;
      }
      SCOPED_TRACE(std::string(mpm::to_string(kernel)) + " " + std::string(mpm::to_string(integrator)));
      // Bounds: 1.5 times the measured maximum of the group; the ratio 16 -> 64 cells measured 2.8-4.1 where
      // the error converges.
      if (kernel == K::ugimp || kernel == K::cpgimp) {
        for (Real e : errors) EXPECT_LT(e, 0.1);
        EXPECT_GT(errors[0] / errors[2], 2.5);
      } else if (kernel == K::bspline2 || kernel == K::bspline3) {
        for (Real e : errors) EXPECT_LT(e, 0.85);
        EXPECT_GT(errors[0] / errors[2], 3.5);
      } else {
        EXPECT_LT(errors[0], 0.2);
        EXPECT_LT(errors[1], 0.4);
        if (integrator != I::usf) {
          EXPECT_LT(errors[2], 1.0);
        }
      }
    }
}

}  // namespace

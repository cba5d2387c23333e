// The consistent mass matrix of Sulsky & Kaul 2004, Eq. (2.2.6), M_ij = sum_p m_p N_i(x_p) N_j(x_p)
// (implicit.mass = "consistent"), against the lumped mass of Eq. (2.2.12) that the paper runs with.
//
// A standing shear wave v_x = V sin(k y) with k h = pi / 4 in a periodic box. With linear elements and the
// lumped mass the grid's frequency would be omega_L = (2 c_s / h) sin(kh / 2). The particles, 2 per cell per
// axis at the quarter points, integrate the mass matrix: the element matrix is m_e [5/16, 3/16; 3/16, 5/16]
// (exact integration: [1/3, 1/6; 1/6, 1/3]), whose eigenvalue per unit mass on the mode is s = 5/8 + 3/8 cos
// kh; the stiffness is integrated exactly (its gradients are constant in a cell). So the consistent mass
// gives omega^2 = omega_L^2 / s. The velocity formulation updates the particles by the grid's velocity change
// (Eq. (2.3.3)) and projects them again at the next step: with the lumped mass that projection of the
// interpolated change is M_L^-1 M, which scales it by s, so the lumped runs oscillate at omega^2 = s
// omega_L^2; the consistent projection M^-1 M is the identity. The two frequencies differ by 1 / s = 1.1234
// (exact integration would give 1 / sqrt(s) = 1.0527 from the mass matrices alone).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "support.hpp"

namespace {
using namespace mpm;
constexpr double pi = 3.14159265358979323846;

// A 1 x 1 box, periodic both ways, 8 x 8 cells (k h = 2 pi / 8), E = 1000, nu = 0.25, rho = 10: shear wave
// speed c_s = sqrt(G / rho) = sqrt(40). theta = 0 (no numerical damping; the step is symplectic Euler, whose
// frequency error (omega dt)^2 / 24 is 2e-5 at cfl = 0.05), V = 1e-4 keeps the strains near 1e-5.
Scene shear_wave(const std::string& mass) {
  std::ostringstream text;
  text << R"toml([simulation]
dimension = 2
end_time = 0.35
integrator = "implicit"
kernel = "linear"
cfl = 0.05
[implicit]
theta = 0
formulation = "velocity"
newton_tolerance = 1e-12
linear_tolerance = 1e-10
mass = ")toml"
       << mass << "\"\n"
       << mpm::testing::periodic_shear_wave;
  return mpm::testing::scene_from_text("consistent_mass", text.str());
}

/// The grid's angular frequency from the peaks of the strain energy, which peaks every half period: pi over
/// the mean spacing of the peak times (each refined by the parabola through its three samples).
double frequency(const std::string& mass) {
  const Scene sc = shear_wave(mass);
  ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  std::vector<double> t, e;
  auto record = [&] {
    double internal = 0;
    for (double ep : sim.state().energy) internal += ep;
    t.push_back(sim.time());
    e.push_back(internal);
  };
  record();
  while (sim.time() < sc.end_time * (1 - 1e-14)) {
    sim.step(sc.end_time - sim.time());
    record();
  }
  std::vector<double> peaks;
  for (std::size_t k = 1; k + 1 < e.size(); ++k)
    if (e[k] > e[k - 1] && e[k] >= e[k + 1]) {
      const double dt = t[k + 1] - t[k], curvature = e[k + 1] - 2 * e[k] + e[k - 1];
      peaks.push_back(t[k] + 0.5 * dt * (e[k - 1] - e[k + 1]) / curvature);
    }
  EXPECT_GE(peaks.size(), 3u);
  return pi * static_cast<double>(peaks.size() - 1) / (peaks.back() - peaks.front());
}

// Measured: lumped 36.5374 against sqrt(s) omega_L = 36.5374, consistent 41.0454 against omega_L / sqrt(s) =
// 41.0444; the tolerance 1e-3 bounds the step's frequency error (2e-5) and the peak fit's.
TEST(ConsistentMass, StandingWaveFollowsEachMassMatrixsDispersion) {
  const double kh = 2 * pi / 8, h = 1.0 / 8, c_s = std::sqrt(40.0);
  const double omega_L = 2 * c_s / h * std::sin(kh / 2), s = 5.0 / 8 + 3.0 / 8 * std::cos(kh);
  const double lumped = frequency("lumped"), consistent = frequency("consistent");
  std::printf("omega: lumped %.6f (theory %.6f), consistent %.6f (theory %.6f)\n", lumped,
              omega_L * std::sqrt(s), consistent, omega_L / std::sqrt(s));
  EXPECT_NEAR(lumped / (omega_L * std::sqrt(s)), 1, 1e-3);
  EXPECT_NEAR(consistent / (omega_L / std::sqrt(s)), 1, 1e-3);
}

// The elastic bar (Sec. 3.1.1) at 100 x the explicit step with the consistent mass, its rigid puller and its
// symmetry face: the quasi-static stress E v t / l = 33.33 at t = 10 as with the lumped mass (measured within
// 2e-5 of it).
TEST(ConsistentMass, ElasticBarReachesTheAnalyticStress) {
  const std::filesystem::path scene =
      std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() /
      "examples/implicit/elastic-bar.toml";
  const Scene sc = read_scene(scene, {"implicit.formulation=\"velocity\"", "implicit.mass=\"consistent\"",
                                      "implicit.step_factor=100", "implicit.start_factor=100"});
  ImplicitSimulation<2, LinearKernel> sim(make_implicit_spec<2>(sc), seed_bodies<2>(sc));
  sim.run_until(10.0);
  mpm::testing::Spread sxx;
  for (const SymTensor<3>& t : sim.state().sigma) sxx.add(t(0, 0));
  const double expected = 1000 * 0.001 * 10 / 0.3;  // Sulsky & Kaul 2004, Eq. (3.1.1)
  std::printf("sigma_xx in [%.7f, %.7f], expected %.7f\n", sxx.min, sxx.max, expected);
  EXPECT_NEAR(sxx.min, expected, 1e-4 * expected);
  EXPECT_NEAR(sxx.max, expected, 1e-4 * expected);
}

}  // namespace

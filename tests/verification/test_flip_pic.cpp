// The FLIP-PIC blend of the particle velocity update ([simulation] flip_fraction), in both engines, on a
// standing wave in a periodic 1-D bar (quadratic B-splines, 2 particles per cell, 32 cells per wavelength, 80
// steps per period). One P2G-G2P round trip multiplies a velocity mode of wavenumber k by the kernel's filter
// G = sinc^6(kh / 2) (the quadratic B-spline's Fourier transform, squared: the mass-weighted P2G and the G2P
// each apply it once on a uniformly filled grid), so a blend alpha multiplies it by 1 - (1 - alpha)(1 - G)
// per step. Half the energy of a standing wave is kinetic on average, so its energy falls as exp(-(1 -
// alpha)(1 - G) t / dt): against FLIP's own, to 0.4641 after one period with PIC and to 0.6813 with alpha =
// 1/2. Measured: 0.4674 and 0.6850 (explicit USL), 0.4664 and 0.6840 (implicit), 0.5% to 0.7% above: the
// estimate averages the kinetic share over the period. Asserted to 2%.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "scene_simulation.hpp"
#include "support.hpp"

namespace {
using namespace mpm;

constexpr double cells = 32, dt = 1.25e-4, period = 0.01;  // c = sqrt(E / rho) = 100 m/s over 1 m

Scene wave(const std::string& integrator, double flip_fraction) {
  std::ostringstream text;
  text << "[simulation]\ndimension = 1\nend_time = " << period << "\ndt = " << dt << "\nintegrator = \""
       << integrator << "\"\nkernel = \"bspline2\"\nflip_fraction = " << flip_fraction << "\n"
       << R"toml(
[grid]
lo = [0.0]
hi = [1.0]
cells = [32]
faces = { x-min = "periodic", x-max = "periodic" }
[[materials]]
name = "m"
model = "hypoelastic"
E = 1e4
nu = 0.0
density = 1.0
[[bodies]]
shape = "box"
lo = [0.0]
hi = [1.0]
velocity = ["0.01 * sin(2 * pi * x)"]
)toml";
  if (integrator == "implicit") text << "[implicit]\ntheta = 0.5\n";
  return mpm::testing::scene_from_text("flip-pic", text.str());
}

/// Kinetic plus internal energy [J per unit area] at the end of one period.
double energy_after_a_period(const std::string& integrator, double flip_fraction) {
  const Scene sc = wave(integrator, flip_fraction);
  const auto energy = [](const ParticleSet<1>& p) {
    double e = 0;
    for (std::size_t i = 0; i < p.size(); ++i) e += 0.5 * p.m[i] * p.v[i].squaredNorm() + p.state.energy[i];
    return e;
  };
  double out = 0;
  mpm::testing::with_scene_simulation<1>(sc, [&](auto& sim) {
    sim.run_until(sc.end_time);
    out = energy(sim.particles());
  });
  return out;
}

/// exp(-(1 - alpha)(1 - G) t / dt) after one period.
double predicted(double flip_fraction) {
  const double x = std::numbers::pi / cells;  // kh / 2
  const double G = std::pow(std::sin(x) / x, 6);
  return std::exp(-(1 - flip_fraction) * (1 - G) * period / dt);
}

/// PIC's and the half blend's energy against FLIP's, in the same engine: FLIP's own loss (the explicit step's
/// 0.9906 of E0 after a period; the implicit step's own dissipation, to 0.78 at theta = 1/2) divides out.
void expect_pic_filter(const std::string& integrator) {
  const double E0 = 0.5 * 1.0 * 0.01 * 0.01 * 0.5;  // rho v0^2 / 4 over the 1 m bar
  const double flip = energy_after_a_period(integrator, 1);
  const double half = energy_after_a_period(integrator, 0.5);
  const double pic = energy_after_a_period(integrator, 0);
  EXPECT_NEAR(pic / flip, predicted(0), 0.02 * predicted(0));
  EXPECT_NEAR(half / flip, predicted(0.5), 0.02 * predicted(0.5));
  if (integrator != "implicit") {
    EXPECT_GT(flip / E0, 0.99) << "FLIP keeps the wave's energy";
  }
  std::printf(
      "%s: E/E0 FLIP %.4f, half %.4f, PIC %.4f; PIC/FLIP %.4f (predicted %.4f), half/FLIP %.4f (%.4f)\n",
      integrator.c_str(), flip / E0, half / E0, pic / E0, pic / flip, predicted(0), half / flip,
      predicted(0.5));
}

TEST(FlipPic, ExplicitPicFiltersTheWaveByTheKernelsRoundTrip) {
  expect_pic_filter("usl");
}

TEST(FlipPic, ImplicitPicFiltersTheWaveByTheKernelsRoundTrip) {
  expect_pic_filter("implicit");
}

TEST(FlipPic, FlipFractionOutsideZeroToOneIsRefused) {
  EXPECT_THROW(wave("usl", 1.5), InputError);
  EXPECT_THROW(wave("usl", -0.1), InputError);
}

}  // namespace

#pragma once
// The freely spinning Neo-Hookean disk of the APIC and CPDI tests: radius 0.3 about (0.5, 0.5) in the unit
// square, spinning at 1 rad/s, no gravity, no wall; 2 particles per cell.
#include <sstream>
#include <string>

#include "mpm/scene/scene.hpp"
#include "support.hpp"

namespace mpm::testing {

struct SpinningDisk {
  std::string integrator;  ///< "usl", ..., or "implicit" (midpoint rule, theta = 1/2)
  std::string kernel;
  std::string transfer_line;  ///< the [simulation] line choosing the transfer, or none
  int cells;                  ///< per axis
  Real E;                     ///< Young's modulus [Pa] (nu = 0.3, density 1)
  Real end_time;
  int step_factor = 1;  ///< implicit steps per explicit CFL step
};

inline Scene spinning_disk_scene(const SpinningDisk& d) {
  std::ostringstream text;
  text.precision(17);
  text << "[simulation]\ndimension = 2\nend_time = " << d.end_time << "\ncfl = 0.4\nintegrator = \""
       << d.integrator << "\"\nkernel = \"" << d.kernel << "\"\n"
       << d.transfer_line << "\n[grid]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\n"
       << "cells = [" << d.cells << ", " << d.cells << "]\n[[materials]]\nname = \"m\"\nE = " << d.E
       << "\nnu = 0.3\ndensity = 1.0\n"
       << R"toml([[bodies]]
shape = "disk"
center = [0.5, 0.5]
radius = 0.3
velocity = ["-(y - 0.5)", "x - 0.5"]
)toml";
  if (d.integrator == "implicit") text << "[implicit]\ntheta = 0.5\nstep_factor = " << d.step_factor << "\n";
  return scene_from_text("spinning-disk", text.str());
}

}  // namespace mpm::testing

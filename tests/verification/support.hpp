#pragma once
// Helpers of the verification tests.
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mpm/scene/scene.hpp"

namespace mpm::testing {

/// The scene whose TOML text is `text`, read through a temporary file "NAME_PID.toml".
inline Scene scene_from_text(const std::string& name, const std::string& text) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(file) << text;
  Scene sc = read_scene(file);
  std::filesystem::remove(file);
  return sc;
}

/// The grid, material and body of a standing shear wave, to follow a scene's [simulation] and [implicit]
/// tables: a 1 x 1 box periodic both ways, 8 x 8 cells, filled with hypoelastic material (E = 1000, nu =
/// 0.25, rho = 10: shear wave speed c_s = sqrt(G / rho) = sqrt(40)) moving at v_x = 1e-4 sin(2 pi y), small
/// enough to be linear.
inline constexpr const char* periodic_shear_wave = R"toml([grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [8, 8]
faces = { x-min = "periodic", x-max = "periodic", y-min = "periodic", y-max = "periodic" }
[[materials]]
name = "m"
model = "hypoelastic"
E = 1000.0
nu = 0.25
density = 10.0
[[bodies]]
shape = "box"
lo = [0.0, 0.0]
hi = [1.0, 1.0]
velocity = ["1e-4 * sin(2 * _pi * y)", 0]
)toml";

/// Least-squares slope of y against x.
inline double fitted_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    n += 1;
    sx += x[k];
    sy += y[k];
    sxx += x[k] * x[k];
    sxy += x[k] * y[k];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// The smallest and largest of the values added.
struct Spread {
  double min = 1e300, max = -1e300;
  void add(double v) {
    min = std::min(min, v);
    max = std::max(max, v);
  }
};

}  // namespace mpm::testing

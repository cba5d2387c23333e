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

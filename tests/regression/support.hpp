#pragma once
// Helpers of the command-line tests: files, scratch folders, and a scene large enough to act on while it runs.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mpm::testing {

/// The whole content of a file (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& f) {
  std::ifstream is(f, std::ios::binary);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

/// A fresh temporary folder "PREFIX_NAME_PID", empty.
inline std::filesystem::path scratch(const std::string& prefix, const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / (prefix + "_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// A 2-D elastic block on a fixed floor, 129,600 particles (300 x 300 cells, the block 0.6 x 0.6 m at 2 per
/// cell): large enough that a step and a checkpoint (~19 MB) take milliseconds, for tests that act while a run
/// is going. The scene file's text, ending at `end_time` [s].
inline std::string block_scene(const std::string& end_time) {
  return "[simulation]\nend_time = " + end_time + R"(
cfl = 0.5
integrator = "usl"
kernel = "linear"
[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [300, 300]
faces = { y-min = "fixed" }
[[materials]]
name = "m"
E = 1e6
nu = 0.3
density = 1000
[[bodies]]
shape = "box"
lo = [0.2, 0.0]
hi = [0.8, 0.6]
velocity = [0.0, "-0.1 * y"]
)";
}

}  // namespace mpm::testing

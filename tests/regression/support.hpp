#pragma once
// Helpers of the command-line tests: running `mpm run`, files, CSV columns, scratch folders, and a scene
// large enough to act on while it runs.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace mpm::testing {

/// The whole content of a file (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& f) {
  std::ifstream is(f, std::ios::binary);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

/// `mpm run FILE --quiet ARGS`, its output in `log`; the exit status (-1 when it did not exit).
inline int run_mpm(const std::filesystem::path& file, const std::string& args,
                   const std::filesystem::path& log) {
  const std::string cmd =
      std::string(MPM_BINARY) + " run " + file.string() + " --quiet " + args + " >" + log.string() + " 2>&1";
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

/// A CSV with a header line (history.csv, newton.csv) as columns by name.
inline std::map<std::string, std::vector<double>> csv_columns(const std::filesystem::path& file) {
  std::ifstream is(file);
  std::string line;
  std::getline(is, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');) names.push_back(h);
  std::map<std::string, std::vector<double>> out;
  while (std::getline(is, line)) {
    std::stringstream ls(line);
    std::string cell;
    for (std::size_t k = 0; k < names.size() && std::getline(ls, cell, ','); ++k)
      out[names[k]].push_back(std::stod(cell));
  }
  return out;
}

/// The values of point array `name` of a .vtp the engine wrote (raw appended data, UInt64 block counts), as
/// doubles, or with an empty name the points' coordinates; empty when the file or the array is missing.
inline std::vector<double> vtp_array(const std::filesystem::path& file, const std::string& name) {
  const std::string text = slurp(file);
  const std::size_t tag = text.find(name.empty() ? std::string("<Points>") : "Name=\"" + name + "\"");
  const std::size_t data = text.find("<AppendedData encoding=\"raw\">\n_");
  if (tag == std::string::npos || data == std::string::npos) return {};
  const std::size_t open = name.empty() ? text.find("<DataArray", tag) : text.rfind("<DataArray", tag);
  const std::string int64 = "<DataArray type=\"Int64\"";
  const bool integer = text.compare(open, int64.size(), int64) == 0;
  const std::size_t at = text.find("offset=\"", open) + 8;
  const std::size_t block = data + 31 + std::stoull(text.substr(at, text.find('"', at) - at));
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, text.data() + block, 8);
  std::vector<double> out(bytes / 8);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const char* v = text.data() + block + 8 + 8 * k;
    if (integer) {
      std::int64_t i = 0;
      std::memcpy(&i, v, 8);
      out[k] = static_cast<double>(i);
    } else {
      std::memcpy(&out[k], v, 8);
    }
  }
  return out;
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
/// cell): large enough that a step and a checkpoint (~19 MB) take milliseconds, for tests that act while a
/// run is going. The scene file's text, ending at `end_time` [s].
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

/// An elastic block 0.2 x 0.4 m (80 kg per metre of thickness) thrown down at 1 m/s under gravity, spreading
/// sideways as it goes, through the outflow face y = 0 of a 0.4 x 0.6 m grid: the scene file's text.
inline std::string outflow_scene() {
  return R"toml([simulation]
end_time = 0.2
cfl = 0.4
integrator = "usl"
kernel = "cpgimp"
[output]
every = 0.05
[loads]
gravity = [0.0, -9.81]
[grid]
lo = [0.0, 0.0]
hi = [0.4, 0.6]
cells = [8, 12]
faces = { y-min = "outflow" }
[[materials]]
name = "m"
E = 1e5
nu = 0.3
density = 1000
[[bodies]]
shape = "box"
lo = [0.1, 0.05]
hi = [0.3, 0.45]
velocity = ["0.5 * (x - 0.2)", -1.0]
)toml";
}

}  // namespace mpm::testing

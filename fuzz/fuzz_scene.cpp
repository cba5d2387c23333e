// libFuzzer target: the scene reader on arbitrary bytes. The input is a scene file; lines of it that start
// with
// "#--set " are --set overrides, and whatever follows a line "#--particles" is written as the particle CSV
// file "particles.csv" beside the scene. A scene that reads is budgeted and, when small, seeded (expressions,
// particle file rows). Bad input must end in mpm::InputError; any other exception, crash, leak or hang is a
// finding, and so is a scene accepted with a first step or step count that is not a finite positive number (E
// = 1.7e308 overflowed the wave speed; an initial speed of 1e154 m/s overflowed |v|^2: issue 47, items 3 and
// 4). fuzz_scene.dict gives the fuzzer huge finite values and deep keys to try.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace fs = std::filesystem;

namespace {
const fs::path& work_dir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("mpm_fuzz_scene_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

/// A run the reader accepted must have a time step and a step count it can take.
void check_steps(const mpm::Budget& budget) {
  if (!(budget.first_dt > 0 && std::isfinite(budget.first_dt) && budget.steps >= 1 &&
        std::isfinite(budget.steps)))
    __builtin_trap();
}

template <int Dim>
void seed(const mpm::Scene& scene) {
  const mpm::ParticleSet<Dim> p = mpm::seed_bodies<Dim>(scene);
  check_steps(mpm::estimate_budget(scene, mpm::fastest_speed<Dim>(p.v)));
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string marker = "#--particles\n";
  const std::size_t split = input.find(marker);
  const std::string scene_text = input.substr(0, split);
  const std::string particles = split == std::string::npos ? "" : input.substr(split + marker.size());
  std::vector<std::string> overrides;
  std::istringstream lines(scene_text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("#--set ", 0) == 0) overrides.push_back(line.substr(7));

  const fs::path scene_file = work_dir() / "scene.toml";
  std::ofstream(scene_file, std::ios::binary | std::ios::trunc) << scene_text;
  std::ofstream(work_dir() / "particles.csv", std::ios::binary | std::ios::trunc) << particles;
  try {
    const mpm::Scene scene = mpm::read_scene(scene_file, overrides);
    const mpm::Budget budget = mpm::estimate_budget(scene);
    (void)mpm::describe(budget);
    check_steps(budget);
    if (budget.particles > 20000 || budget.nodes > 1e6) return 0;  // seeding cost, not a finding
    if (scene.dim == 1) seed<1>(scene);
    if (scene.dim == 2) seed<2>(scene);
    if (scene.dim == 3) seed<3>(scene);
  } catch (const mpm::InputError&) {
  }
  return 0;
}

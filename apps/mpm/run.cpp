// `mpm run SCENE` and `mpm render DIR`: run a scene file with its outputs, and draw pictures of the results.
#include "mpm/run/run.hpp"

#include <unistd.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "commands.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/scene/scene.hpp"
#include "python_tool.hpp"

namespace mpm::app {

namespace {
namespace fs = std::filesystem;

/// The output folder must be a folder we can write, or a path that can be made one: checked without
/// creating anything, so that a refused run writes nothing.
void check_output_folder(const fs::path& out) {
  std::error_code ec;
  fs::path at = fs::absolute(out, ec);
  const std::string where = "--out " + out.string() + ": ";
  if (fs::exists(at, ec) && !fs::is_directory(at, ec)) throw InputError(where + "exists and is not a folder");
  while (!fs::exists(at, ec) && at.has_parent_path() && at != at.parent_path()) at = at.parent_path();
  if (!fs::is_directory(at, ec))
    throw InputError(where + "cannot make the folder: " + at.string() + " is not a folder");
  // Probe with a folder made and removed at once: permissions alone do not tell (/proc, read-only mounts).
  const fs::path probe = at / (".mpm-probe-" + std::to_string(::getpid()));
  if (!fs::create_directory(probe, ec) || ec)
    throw InputError(where + "cannot write in " + at.string() + (ec ? ": " + ec.message() : ""));
  fs::remove(probe, ec);
}

/// "8G", "512M", "1.5e9": bytes with an optional K, M, G or T suffix (powers of 1024).
double parse_bytes(const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  const std::string suffix = text.substr(used);
  static const std::string units = "KMGT";
  double scale = 1;
  if (suffix.size() == 1 && units.find(static_cast<char>(std::toupper(suffix[0]))) != std::string::npos)
    scale =
        std::pow(1024.0, 1.0 + static_cast<double>(units.find(static_cast<char>(std::toupper(suffix[0])))));
  else if (!suffix.empty())
    used = 0;
  if (used == 0 || !(value > 0) || !std::isfinite(value))
    throw InputError("--max-memory: expected a positive size such as 8G, 512M or 2e9 (bytes), got '" + text +
                     "'");
  return value * scale;
}
}  // namespace

Action add_run(CLI::App& app) {
  struct Options {
    std::string scene;
    std::vector<std::string> overrides;
    RunOptions run;
    std::string out = "out";
    std::string restart;
    std::string max_memory;
    bool dry_run = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("run", "run a scene file (TOML; see docs/scene-format.md)");
  cmd->add_option("scene", o->scene, "the scene file")->required();
  cmd->add_option("--out", o->out, "output folder (default: out)");
  cmd->add_option("--threads", o->run.threads, "threads (default: the scene's, else all cores)");
  cmd->add_option("--set", o->overrides,
                  "override a scene value, e.g. --set simulation.end_time=0.5 (repeatable)");
  cmd->add_flag("--quiet", o->run.quiet, "no progress line");
  cmd->add_option("--checkpoint-every", o->run.checkpoint_every,
                  "write OUT/checkpoint.h5 every this many steps");
  cmd->add_option("--restart", o->restart, "continue from a checkpoint written by this scene");
  cmd->add_option("--stop-after", o->run.stop_after,
                  "stop after this many steps, writing OUT/checkpoint.h5 to continue from with --restart");
  cmd->add_option(
      "--max-memory", o->max_memory,
      "refuse runs estimated to need more memory, e.g. 8G (default: the machine's physical memory)");
  cmd->add_flag("--dry-run", o->dry_run, "check the scene and print the run's budget; write nothing");
  return [o]() {
    if (o->run.threads < 0 || o->run.threads > max_threads)
      throw InputError("--threads: expected a non-negative count of at most " + std::to_string(max_threads) +
                       ", got " + std::to_string(o->run.threads));
    if (o->run.stop_after < 0) throw InputError("--stop-after: expected a non-negative step count");
    if (o->run.checkpoint_every < 0)
      throw InputError("--checkpoint-every: expected a non-negative step count");
    if (!o->restart.empty() && !std::filesystem::exists(o->restart))
      throw InputError("--restart: no checkpoint at " + o->restart);
    if (o->out.empty()) throw InputError("--out: expected a folder");
    const Scene scene = read_scene(o->scene, o->overrides);
    check_output_folder(o->out);
    const Budget budget = estimate_budget(scene);
    // A restart's output is checked against what is left of the run once its checkpoint is read (SceneRun).
    const BudgetLimits limits{
        o->max_memory.empty() ? physical_memory_bytes() : parse_bytes(o->max_memory),
        o->restart.empty() ? free_space_bytes(o->out) : std::numeric_limits<double>::infinity()};
    check_budget(scene, budget, limits);
    o->run.out_dir = o->out;
    o->run.restart = o->restart;
    o->run.dry_run = o->dry_run;
    const int status = run_scene(scene, o->run);
    if (o->dry_run) return status;
    if (!o->run.quiet && world().rank() == 0)
      std::cout << (status == 0 ? "done" : "failed") << ": " << o->out << "/particles.pvd (ParaView), "
                << o->out << "/history.csv, " << o->out << "/summary.json\n";
    return status;
  };
}

Action add_render(CLI::App& app) {
  struct Options {
    std::string dir;
    std::string field = "velocity";
    int every = 1;
    std::string plane = "xy";
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "render", "draw PNG pictures of a run's particles in a coordinate plane (needs python3-matplotlib)");
  cmd->add_option("dir", o->dir, "the output folder of `mpm run`")->required();
  cmd->add_option("--field", o->field, "field to colour by, e.g. velocity, J, stress:0 (a component)");
  cmd->add_option("--every", o->every, "draw every K-th output (the last is always drawn)");
  cmd->add_option("--plane", o->plane,
                  "coordinate plane to draw: xy (default), xz or yz (3-D runs: a projection)");
  return [o]() {
    if (o->every < 1) throw InputError("--every: expected a positive integer");
    if (o->plane != "xy" && o->plane != "xz" && o->plane != "yz")
      throw InputError("--plane: expected xy, xz or yz, got '" + o->plane + "'");
    if (!std::filesystem::exists(std::filesystem::path(o->dir) / "particles.pvd"))
      throw InputError("render: no particles.pvd in " + o->dir + " (run `mpm run SCENE --out " + o->dir +
                       "` first)");
    run_python("render", {o->dir, o->field, std::to_string(o->every), o->plane}, "mpm render");
    return 0;
  };
}

}  // namespace mpm::app

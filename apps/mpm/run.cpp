// `mpm run SCENE` and `mpm render DIR`: run a scene file with its outputs, and draw pictures of the results.
#include <iostream>

#include "commands.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/scene/run.hpp"
#include "mpm/scene/scene.hpp"
#include "python_tool.hpp"

namespace mpm::app {

Action add_run(CLI::App& app) {
  struct Options {
    std::string scene;
    std::vector<std::string> overrides;
    RunOptions run;
    std::string out = "out";
    std::string restart;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("run", "run a scene file (TOML; see docs/scene-format.md)");
  cmd->add_option("scene", o->scene, "the scene file")->required();
  cmd->add_option("--out", o->out, "output folder (default: out)");
  cmd->add_option("--threads", o->run.threads, "threads (default: the scene's, else all cores)");
  cmd->add_option("--set", o->overrides, "override a scene value, e.g. --set simulation.end_time=0.5 (repeatable)");
  cmd->add_flag("--quiet", o->run.quiet, "no progress line");
  cmd->add_option("--checkpoint-every", o->run.checkpoint_every, "write OUT/checkpoint.h5 every this many steps");
  cmd->add_option("--restart", o->restart, "continue from a checkpoint written by this scene");
  cmd->add_option("--stop-after", o->run.stop_after,
                  "stop after this many steps, writing OUT/checkpoint.h5 to continue from with --restart");
  return [o]() {
    if (o->run.threads < 0) throw InputError("--threads: expected a non-negative count");
    if (o->run.stop_after < 0) throw InputError("--stop-after: expected a non-negative step count");
    if (o->run.checkpoint_every < 0) throw InputError("--checkpoint-every: expected a non-negative step count");
    if (!o->restart.empty() && !std::filesystem::exists(o->restart))
      throw InputError("--restart: no checkpoint at " + o->restart);
    const Scene scene = read_scene(o->scene, o->overrides);
    o->run.out_dir = o->out;
    o->run.restart = o->restart;
    const int status = run_scene(scene, o->run);
    if (!o->run.quiet)
      std::cout << (status == 0 ? "done" : "failed") << ": " << o->out << "/particles.pvd (ParaView), " << o->out
                << "/history.csv, " << o->out << "/summary.json\n";
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
  CLI::App* cmd = app.add_subcommand("render", "draw PNG pictures of a run's particles in a coordinate plane (needs python3-matplotlib)");
  cmd->add_option("dir", o->dir, "the output folder of `mpm run`")->required();
  cmd->add_option("--field", o->field, "field to colour by, e.g. velocity, J, stress:0 (a component)");
  cmd->add_option("--every", o->every, "draw every K-th output (the last is always drawn)");
  cmd->add_option("--plane", o->plane, "coordinate plane to draw: xy (default), xz or yz (3-D runs: a projection)");
  return [o]() {
    if (o->every < 1) throw InputError("--every: expected a positive integer");
    if (o->plane != "xy" && o->plane != "xz" && o->plane != "yz")
      throw InputError("--plane: expected xy, xz or yz, got '" + o->plane + "'");
    if (!std::filesystem::exists(std::filesystem::path(o->dir) / "particles.pvd"))
      throw InputError("render: no particles.pvd in " + o->dir + " (run `mpm run SCENE --out " + o->dir + "` first)");
    run_python("render", {o->dir, o->field, std::to_string(o->every), o->plane}, "mpm render");
    return 0;
  };
}

}  // namespace mpm::app

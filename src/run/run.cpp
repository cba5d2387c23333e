#include "mpm/run/run.hpp"

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "scene_entry.hpp"

namespace mpm {

int run_scene(const Scene& scene, const RunOptions& options) {
  set_num_threads(options.threads > 0 ? options.threads : scene.threads);
  if (options.checkpoint_every < 0)
    throw InputError("--checkpoint-every: expected a non-negative step count");
  if (options.out_dir.empty()) throw InputError("--out: expected a folder for the outputs");
  switch (scene.dim) {
    case 1:
      return run_scene_on<1>(scene, options, engine_of<1>(scene));
    case 2:
      return run_scene_on<2>(scene, options, engine_of<2>(scene));
    default:
      return run_scene_on<3>(scene, options, engine_of<3>(scene));
  }
}

}  // namespace mpm

#include "mpm/run/session.hpp"

#include <limits>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/scene/budget.hpp"
#include "scene_entry.hpp"

namespace mpm {

std::unique_ptr<Session> open_session(const Scene& scene, const RunOptions& options) {
  if (options.threads < 0 || options.threads > max_threads)
    throw InputError("threads: expected a non-negative count of at most " + std::to_string(max_threads) +
                     " (0: the scene's setting), got " + std::to_string(options.threads));
  if (options.checkpoint_every < 0) throw InputError("checkpoint_every: expected a non-negative step count");
  // The limits `mpm run` checks before anything large is allocated (apps/mpm/run.cpp), with the same
  // messages.
  check_budget(scene, estimate_budget(scene),
               {physical_memory_bytes(), options.out_dir.empty() ? std::numeric_limits<double>::infinity()
                                                                 : free_space_bytes(options.out_dir)});
  set_num_threads(options.threads > 0 ? options.threads : scene.threads);
  switch (scene.dim) {
    case 1:
      return open_session_on<1>(scene, options, engine_of<1>(scene));
    case 2:
      return open_session_on<2>(scene, options, engine_of<2>(scene));
    default:
      return open_session_on<3>(scene, options, engine_of<3>(scene));
  }
}

}  // namespace mpm

#include "mpm/run/session.hpp"

#include <limits>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/shape/kernel_policies.hpp"
#include "scene_entry.hpp"

namespace mpm {

namespace {

template <int Dim>
std::unique_ptr<Session> open_in(const Scene& sc, const RunOptions& o) {
  return with_kernel<Dim>(sc.kernel, [&]<class Kernel>() -> std::unique_ptr<Session> {
    if (sc.implicit) return open_session_on<Dim, scene_engines::Implicit<Dim, Kernel>>(sc, o);
    return open_session_on<Dim, scene_engines::Explicit<Dim, Kernel>>(sc, o);
  });
}
}  // namespace

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
      return open_in<1>(scene, options);
    case 2:
      return open_in<2>(scene, options);
    default:
      return open_in<3>(scene, options);
  }
}

}  // namespace mpm

#include "mpm/run/run.hpp"

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/shape/kernel_policies.hpp"
#include "scene_entry.hpp"

namespace mpm {

namespace {
template <int Dim>
int run_in(const Scene& sc, const RunOptions& o) {
  return with_kernel<Dim>(sc.kernel, [&]<class Kernel>() {
    if (sc.implicit) return run_scene_on<Dim, scene_engines::Implicit<Dim, Kernel>>(sc, o);
    return run_scene_on<Dim, scene_engines::Explicit<Dim, Kernel>>(sc, o);
  });
}
}  // namespace

int run_scene(const Scene& scene, const RunOptions& options) {
  set_num_threads(options.threads > 0 ? options.threads : scene.threads);
  if (options.checkpoint_every < 0)
    throw InputError("--checkpoint-every: expected a non-negative step count");
  if (options.out_dir.empty()) throw InputError("--out: expected a folder for the outputs");
  switch (scene.dim) {
    case 1:
      return run_in<1>(scene, options);
    case 2:
      return run_in<2>(scene, options);
    default:
      return run_in<3>(scene, options);
  }
}

}  // namespace mpm

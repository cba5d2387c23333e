#pragma once
/// Running a scene: the time loop with its outputs (ParaView files, history, summary, progress, checkpoints).
#include <cstdint>
#include <filesystem>

#include "mpm/scene/scene.hpp"

namespace mpm {

struct RunOptions {
  std::filesystem::path out_dir = "out";
  int threads = 0;                    ///< 0: the scene's setting (0 there too: all cores)
  bool quiet = false;                 ///< no progress line
  std::int64_t checkpoint_every = 0;  ///< steps between checkpoints (out_dir/checkpoint.h5); 0: none
  std::filesystem::path restart;      ///< a checkpoint of this scene to continue from; empty: start at t = 0
  std::int64_t stop_after =
      0;                 ///< stop after this many steps of this run (with a checkpoint); 0: run to the end
  bool dry_run = false;  ///< set the run up (particles, restart) and print its budget; write nothing
};

/// Run the scene to its end time, after printing its budget (estimate_budget) on stdout. Writes into out_dir:
/// particles_NNNN.vtp and particles.pvd (every output.every of simulated time, and the first and last
/// states), history.csv (every step), summary.json, and checkpoint.h5 when asked. Input errors throw
/// InputError before anything is written. Returns 0, or exit_simulation_failure after a numerical failure or
/// when memory runs out: the outputs then hold every good state, summary.json says "failed" and why, and the
/// last checkpoint is kept (implicit runs, and explicit ones whose memory ran out between steps, write one of
/// the last good state). SIGINT or SIGTERM stops the run after its current step with a checkpoint and
/// summary.json "interrupted", returning 130 or 143 (a second signal ends the program at once). Throws
/// OutputError naming the file when an output cannot be written; the checkpoint written before then stays
/// readable.
int run_scene(const Scene& scene, const RunOptions& options);

}  // namespace mpm

#pragma once
/// What a run of a scene will cost, estimated from the scene alone before anything large is allocated:
/// particles per body, grid nodes, memory, steps and output volume; and the limits a run must stay within.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mpm/scene/scene.hpp"

namespace mpm {

/// The particles one body will seed: exact for boxes and particle files, the lattice count times the shape's
/// share of its bounding box for disks, spheres and rings (within a few percent for 10 or more particles
/// across).
struct BodyEstimate {
  std::string name;  ///< "bodies[K] (NAME)"
  double particles = 0;
};

struct Budget {
  std::vector<BodyEstimate> bodies;
  double particles = 0;
  double nodes = 0;         ///< grid nodes, ghost layers included
  double memory_bytes = 0;  ///< engine arrays plus the run's own buffers at their peak [B]
  double first_dt = 0;      ///< the first step [s]; for a CFL step, from the wave speed at rest plus the
                            ///< fastest particle's initial speed
  double steps = 0;         ///< (end_time - start time) / first_dt (at least one)
  double frames = 0;        ///< particle outputs (particles_NNNN.vtp) the run adds
  double output_bytes = 0;  ///< frames, history.csv, newton.csv, summary, one checkpoint and its copy [B]
};

/// Where a run may write and how much memory it may use.
struct BudgetLimits {
  double max_memory_bytes = 0;  ///< refuse runs estimated to need more
  double free_bytes = 0;        ///< free space under the output folder
};

/// The largest values the scene reader accepts, so that absurd input is refused with a line naming the key.
namespace limits {
inline constexpr std::int64_t max_cells_per_axis = 1'000'000;
inline constexpr double max_nodes = 2147483647.0;      ///< node indices are 32-bit
inline constexpr double max_particles = 2147483647.0;  ///< particle indices are 32-bit
inline constexpr int max_ppc = 16;                     ///< particles per cell per axis
inline constexpr double max_frames = 100'000;
inline constexpr double max_steps = 1e9;
}  // namespace limits

/// Estimate the cost of running `scene` whose fastest particle starts at `initial_speed` [m/s] (0 before the
/// particles are seeded), from `start_time` (a restart's) to its end time.
Budget estimate_budget(const Scene& scene, double initial_speed = 0, double start_time = 0);

/// Throws InputError naming `where` (a body's velocity key) when the fastest particle, at `speed` [m/s],
/// would make the run take more than limits::max_steps steps, or its speed overflows.
void check_initial_speed(const Scene& scene, const std::string& where, double speed);

/// Throws InputError naming the body or key and the estimate when the run exceeds a limit: particles or nodes
/// past 2^31 - 1, more than limits::max_steps steps, memory past max_memory_bytes (the largest body named),
/// output past the free space.
void check_budget(const Scene& scene, const Budget& budget, const BudgetLimits& limits);

/// One line: "budget: N particles, N nodes, B memory, N steps (dt S), N frames, B output".
std::string describe(const Budget& budget);

/// Physical memory of this machine [B].
double physical_memory_bytes();

/// Free space [B] on the file system that holds `path`, or its nearest existing ancestor.
double free_space_bytes(const std::filesystem::path& path);

}  // namespace mpm

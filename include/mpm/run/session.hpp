#pragma once
/// A scene run driven one step at a time (the Python module's Simulation): the same engine, steps and outputs
/// as `mpm run` (run_scene), with the particle and grid arrays readable between steps.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "mpm/run/run.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {

/// One array of a particle or grid field, (rows, components...) in shape. A view into the engine's storage
/// (`owned` empty: valid until the next step, which may reorder the particles) or a copy (`owned` holds it).
struct FieldArray {
  std::string name;
  char kind = 'f';            ///< NumPy kind: 'f' float, 'i' signed, 'u' unsigned integer
  std::size_t item_size = 8;  ///< bytes per element
  std::vector<std::size_t> shape;
  std::vector<std::ptrdiff_t> strides;  ///< bytes, per axis of shape
  const void* data = nullptr;
  std::shared_ptr<std::vector<double>> owned;  ///< the copy data points into, or null for a view
};

/// Energies and momentum of the particles (every rank's), and the work the loads did since t = 0.
struct SessionTotals {
  double kinetic = 0, strain = 0, external_work = 0, friction_dissipation = 0;
  std::vector<double> momentum;  ///< dim components
};

class Session {
 public:
  virtual ~Session() = default;
  virtual int dim() const = 0;
  virtual double time() const = 0;
  virtual std::int64_t steps() const = 0;
  virtual double end_time() const = 0;
  /// The step the next call to step() will try (the implicit engine may halve it).
  virtual double next_dt() const = 0;
  /// One whole step and its outputs (RunOptions::out_dir). Throws SimulationFailure on a numerical failure
  /// (the outputs then say so, as `mpm run` does) and InputError when the scene has already ended.
  virtual void step() = 0;
  /// The end of the run's outputs: the last frame, a checkpoint when asked or unfinished, summary.json with
  /// status "ok" at the end time, "stopped" before it, or "failed" after a failure. Later calls do nothing.
  virtual void close() = 0;
  /// A checkpoint of the current state, restartable with RunOptions::restart.
  virtual void checkpoint(const std::filesystem::path& file) = 0;
  virtual SessionTotals totals() const = 0;
  /// The constraints' names (faces, regions, rigid bodies) and the force each applied in the last step, dim
  /// components each (the history's reaction_NAME_x ... columns).
  virtual std::vector<std::string> reaction_names() const = 0;
  virtual std::vector<double> reactions() const = 0;
  /// The particle fields: x, X, velocity, displacement, stress, F, J, volume, mass, material, id, the [check]
  /// error and the engine's own (plastic_strain, ...), as the frames write them (F is dim x dim here).
  virtual std::vector<std::string> particle_field_names() const = 0;
  /// One of them, rows in the engine's current order (id names each particle). A view for x, X, velocity, F,
  /// volume, mass, material and id; a copy of the others. Throws InputError for an unknown name.
  virtual FieldArray particle_field(const std::string& name) const = 0;
  /// Grid fields of velocity field 0, one row per node (ghost layers included, axis 0 fastest): position (a
  /// copy), mass and velocity (views of the last step's nodes).
  virtual std::vector<FieldArray> grid_fields() const = 0;
  /// Nodes per axis of grid_fields()' rows, axis 0 first.
  virtual std::vector<std::size_t> grid_shape() const = 0;
  /// Replace every particle's velocity: `v` holds particles x dim values in the order of particle_fields().
  virtual void set_velocities(const double* v, std::size_t count) = 0;
};

/// Set up a scene run as run_scene does (threads, restart, outputs when out_dir is not empty; dry_run, quiet
/// and stop_after are not used). Throws InputError on bad options.
std::unique_ptr<Session> open_session(const Scene& scene, const RunOptions& options);

}  // namespace mpm

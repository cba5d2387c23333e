#pragma once
// What the run loop (SceneRun, SceneSession, the checkpoints and outputs) asks of an engine in Dim
// dimensions, as one interface: the loop is compiled once per dimension, the engines (engines.hpp: Explicit,
// Implicit) once per kernel. A call through it is made once per step or output, never per particle in a hot
// loop.
#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mpm/contact/multi_field.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/vtk.hpp"
#include "mpm/particles/outflow.hpp"
#include "mpm/particles/particle_sums.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "mpm/transfer/passes.hpp"

namespace mpm {

/// A symmetric tensor's six components in VTK's order, xx yy zz xy yz xz, which ParaView's tensor filters
/// read (SymTensor's own is xx yy zz xy xz yz).
inline void vtk_order(const SymTensor<3>& s, double* out) {
  constexpr int from[6] = {0, 1, 2, 3, 5, 4};
  for (int k = 0; k < 6; ++k) out[k] = s.c[from[k]];
}

template <int Dim>
class SceneEngine {
 public:
  virtual ~SceneEngine() = default;

  // The step and the clock.
  /// One step of at most max_dt [s]; SimulationFailure when it fails.
  virtual void step(Real max_dt) = 0;
  virtual Real time() const = 0;
  virtual std::int64_t steps() const = 0;
  virtual Real next_dt() const = 0;
  /// After a SimulationFailure: whether the particles hold the last good state (true) or the failed step's.
  virtual bool failure_keeps_state() const = 0;

  // The particles, the grid, what left through outflow faces.
  virtual ParticleSet<Dim>& particles() = 0;
  virtual const ParticleSet<Dim>& particles() const = 0;
  virtual const Grid<Dim>& grid() const = 0;
  virtual const Outflow<Dim>& outflow() const = 0;
  virtual void restore_outflow(const Outflow<Dim>& out) = 0;
  virtual void remove_outflow() = 0;
  virtual Transfer transfer() const = 0;
  virtual KernelKind kernel() const = 0;
  /// The velocity fields of [[contact]] (1 without).
  virtual int velocity_fields() const = 0;

  // Sums over every rank's particles.
  virtual const Communicator& communicator() const = 0;
  /// This rank's particles' count, and all ranks'.
  virtual std::int64_t particle_count() const = 0;
  /// Visit this rank's particles as runs [begin, end) of one group each, in the order whose exact sums give
  /// the same bits for any division (exact_particle_sum).
  virtual void for_each_sum_run(const std::function<void(std::size_t, std::size_t)>& visit) const = 0;
  /// sum_p fn(p) over every rank's particles, the same bits whatever the division (exact_run_sum).
  template <std::size_t N, class Fn>
  std::array<Real, N> particle_sum(Fn&& fn) const {
    return exact_run_sum<N>([&](const auto& visit) { for_each_sum_run(visit); }, fn, communicator());
  }

  // Energies and work.
  /// Particle i's internal energy [J]: the stored V0 W(F) of a hyperelastic one (which dissipates nothing),
  /// the accumulated stress work of a rate-form one, stored plus dissipated:
  /// Sulsky & Kaul 2004, Eq. (2.2.16).
  virtual Real internal_energy(std::size_t i) const = 0;
  /// Whether load_power reads the particles' velocities from before the step.
  virtual bool needs_velocities_before() const = 0;
  /// The power of gravity and the body forces over the last step [W].
  virtual Real load_power(const std::vector<Vec<Dim>>& v_before) const = 0;
  /// The power friction dissipated on the Coulomb walls in the last step [W].
  virtual Real friction_power() const = 0;

  // The constraints and contact, as history.csv reports them.
  virtual std::vector<std::string> reaction_names() const = 0;
  virtual std::vector<Vec<Dim>> reactions() const = 0;
  virtual std::vector<Vec<Dim>> reaction_velocities(Real t) const = 0;
  virtual std::vector<PairForces<Dim>> contact_forces() const = 0;
  virtual std::vector<std::string> spread_names() const = 0;
  virtual std::vector<Real> spreads() const = 0;
  /// newton.csv's rows, and history.csv's solver columns.
  virtual std::vector<NewtonAttempt> newton_attempts() const = 0;
  virtual std::vector<std::string> counter_names() const = 0;
  virtual std::vector<std::int64_t> counters() const = 0;

  // Outputs and checkpoints.
  /// Cauchy stress of particle i in VTK's order of a symmetric tensor, xx yy zz xy yz xz (vtk_order).
  virtual void stress(std::size_t i, double* out) const = 0;
  /// The engine's own frame fields (the rate-form state, the contact field).
  virtual void add_fields(std::vector<io::PointField>& fields) const = 0;
  virtual void summarize(nlohmann::json& j) const = 0;
  virtual void save(io::CheckpointData& c) const = 0;
  virtual void load(const io::CheckpointData& c, const std::string& where) = 0;
  /// After every rank loaded its share of a checkpoint.
  virtual void take_particles() = 0;
  /// After a SimulationFailure, for the last state's frame: 1 for each particle that failed, 0 for the
  /// others.
  virtual std::vector<double> failed_particles() const = 0;
};

}  // namespace mpm

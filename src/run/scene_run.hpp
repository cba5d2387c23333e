#pragma once
// The time loop of a scene run with its outputs (ParaView files, history, summary, progress, checkpoints), as
// steps: `mpm run` goes through them in one loop (run_scene), a Session (mpm/run/session.hpp) one call at a
// time.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>

#include "mpm/core/build_info.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/interrupt.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/files.hpp"
#include "mpm/io/vtk.hpp"
#include "mpm/run/run.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/verification/error_norms.hpp"
#include "run_checkpoint.hpp"
#include "run_files.hpp"
#include "run_frame.hpp"
#include "run_history.hpp"
#include "run_progress.hpp"
#include "run_totals.hpp"
#include "scene_engine.hpp"
#include "scene_entry.hpp"

namespace mpm {

/// A scene on one engine, from its start or a checkpoint to its end. With an empty RunOptions::out_dir it
/// writes nothing (a Session that only steps).
template <int Dim>
class SceneRun {
  using Clock = std::chrono::steady_clock;

 public:
  SceneRun(const Scene& sc, const RunOptions& o, EngineFactory<Dim> make)
      : sc_(sc), o_(o), engine_(make(sc)), comm_(engine_->communicator()), root_(comm_.rank() == 0) {
    if (comm_.size() > 1 && o.checkpoint_every > 0 && !io::collective_checkpoints())
      throw InputError(
          "--checkpoint-every: this mpm was built without parallel HDF5 (libhdf5-openmpi-dev), which "
          "the checkpoints of a run divided between ranks need; run in one process to checkpoint");
    if (!o.restart.empty()) {
      try {
        scene_checkpoint::restore<Dim>(io::read_checkpoint(o.restart, comm_), *engine_, acc_,
                                       "--restart " + o.restart.string());
        previous_time_ = engine_->time();
      } catch (
          const InputError& e) {  // name the option: "checkpoint FILE: not an HDF5 file" alone is unclear
        const std::string what = e.what();
        throw InputError(what.rfind("--restart", 0) == 0 ? what : "--restart: " + what);
      }
    }
    // What is left to run, from the particles' speeds: a restart's output fits what remains of the run, not
    // the whole of it (its memory was checked before the particles were built).
    budget_ = estimate_budget(sc_, comm_.max(fastest_speed<Dim>(std::as_const(*engine_).particles().v)),
                              engine_->time());
    if (!o.restart.empty() && writes())
      check_budget(sc_, budget_, {std::numeric_limits<double>::infinity(), free_space_bytes(o_.out_dir)});
  }

  /// The command's loop: the budget on stdout, then open(), advance() to the end time (or --stop-after, or a
  /// signal), and close(). Returns run_scene's exit status.
  int run() {
    if (root_) std::cout << describe(budget_) << std::endl;
    if (o_.dry_run) return 0;
    const InterruptHandlers handlers;
    Progress progress(o_.quiet || !root_, engine_->time(), sc_.end_time);
    progress.start_at(engine_->steps());
    std::string failure;
    int signal = 0;
    try {
      open();
      const std::int64_t stop_at = o_.stop_after > 0 ? engine_->steps() + o_.stop_after : -1;
      try {
        while (!at_end() && engine_->steps() != stop_at && !interrupted()) {
          advance();
          progress.update(engine_->steps(), engine_->time());
        }
      } catch (const SimulationFailure& e) {
        failure = failed(e.what());
      } catch (const std::bad_alloc&) {
        failure = out_of_memory();
      }
      signal = failure.empty() && !at_end() ? static_cast<int>(comm_.max(interrupt_requested())) : 0;
      close(failure, signal);
    } catch (const OutputError& e) {
      abandon(e.what());
      throw;
    }
    if (!failure.empty()) {
      if (root_)
        std::cerr << "mpm: simulation failed: " << failure
                  << (failure_frame_.empty() ? ""
                                             : "; its last state: " + (o_.out_dir / failure_frame_).string())
                  << '\n';
      return exit_simulation_failure;
    }
    if (signal) {
      if (root_)
        std::cerr << "mpm: interrupted by " << signal_name(signal) << " after step " << engine_->steps()
                  << ", t = " << engine_->time() << " s; "
                  << (can_checkpoint()
                          ? "continue with --restart " + (o_.out_dir / "checkpoint.h5").string()
                          : std::string("this mpm writes no checkpoint of a divided run (no parallel HDF5)"))
                  << '\n';
      return exit_interrupted(signal);
    }
    return 0;
  }

  /// The output folder (a restart keeps what came before its checkpoint) with the scene as this run reads it
  /// (scene_as_run.toml: the file with the --set overrides applied), and at step 0 the first frame and
  /// history row.
  void open() {
    wall_start_ = Clock::now();
    if (!writes()) return;
    acc_.frames = files_.prepare(!o_.restart.empty(), engine_->time(), engine_->steps(),
                                 history_header<Dim>(sc_, *engine_), sc_.newton_log);
    if (root_) io::write_file_atomically(o_.out_dir / "scene_as_run.toml", sc_.resolved_text);
    if (engine_->steps() == 0) {
      write_frame();
      write_history_row();
    }
  }

  /// One step and what follows it: the loads' work, outflow, the [check] error, the history row, the Newton
  /// log, a frame when one is due and a checkpoint every checkpoint_every steps. A SimulationFailure or
  /// bad_alloc propagates: pass it to failed() or out_of_memory().
  void advance() {
    if (engine_->needs_velocities_before()) v_before_ = std::as_const(*engine_).particles().v;
    const auto step_start = Clock::now();
    in_step_ = true;
    engine_->step(sc_.end_time - engine_->time());
    in_step_ = false;
    compute_seconds_ += std::chrono::duration<double>(Clock::now() - step_start).count();
    account_work();
    engine_->remove_outflow();
    watch_domains();
    if (has_check()) record_error();
    if (writes()) {
      write_history_row();
      if (files_.newton_log().is_open())
        files_.newton_log().write(engine_->steps(), engine_->newton_attempts());
      if (sc_.output_every > 0 && engine_->time() >= next_output_time() * (1 - 1e-12)) write_frame();
      if (o_.checkpoint_every > 0 && engine_->steps() % o_.checkpoint_every == 0) write_checkpoint();
    }
  }

  /// After a step of a kernel whose half-lengths follow F (cpGIMP): count the particles whose domains the
  /// stencil bounds, and say on stderr when the first appear (summary.json reports them).
  void watch_domains() {
    if (!deforms_half_lengths(engine_->kernel())) return;
    std::vector<std::int64_t> count{bounded_half_lengths(std::as_const(*engine_).particles())};
    comm_.sum(count);
    if (bounded_.observe(engine_->steps(), engine_->time(), count[0]) && root_ && !o_.quiet)
      std::cerr
          << "\rmpm: note: step " << engine_->steps() << ", t = " << engine_->time() << " s: " << count[0]
          << (count[0] == 1 ? " particle's" : " particles'") << " cpGIMP half-lengths l0 F_dd left [l0/4, "
          << (max_half_length(engine_->kernel()) < 1 ? "h/2" : "h")
          << "]; from here on their domains are bounded to it (docs/kernels.md, \"Bounded cpGIMP domains\"; "
             "kernel = \"cpdi\" follows any deformation)\n";
  }

  /// Whether the run reached the scene's end time.
  bool at_end() const { return engine_->time() >= sc_.end_time * (1 - 1e-14); }

  /// After a SimulationFailure in advance(): the engine that keeps its state checkpoints the last good one to
  /// restart from, the Newton log gets the failed step's attempts, and the particles as the failure left them
  /// go to particles_fail.vtp with the failed ones marked. Returns the failure's description.
  std::string failed(const std::string& what) {
    if (writes()) {
      // The implicit engine fails before it touches the particles: checkpoint the last good state to restart
      // from.
      if (engine_->failure_keeps_state()) write_checkpoint();
      if (files_.newton_log().is_open())
        files_.newton_log().write(engine_->steps() + 1, engine_->newton_attempts());
      write_failure_frame();
    }
    return what;
  }
  /// After std::bad_alloc in advance() or in its outputs: the description, and a checkpoint where it is safe.
  std::string out_of_memory() {
    // Steps of the explicit engine allocate nothing: memory ran out in the outputs, after a good step.
    // Among several ranks the others are elsewhere in the step: no checkpoint they would have to join.
    if (writes() && comm_.size() == 1 && (!in_step_ || engine_->failure_keeps_state())) write_checkpoint();
    return "out of memory at step " + std::to_string(engine_->steps() + 1) + " (estimated need " +
           std::to_string(budget_.memory_bytes / 1e6) + " MB)";
  }

  /// The end of the run: after a good one the last frame, then a checkpoint when asked or when it stopped
  /// early, and summary.json with the status ("ok", "stopped", "interrupted" by `signal`, or "failed" with
  /// `failure`).
  void close(const std::string& failure, int signal = 0) {
    if (!writes()) return;
    const bool unfinished = !at_end();
    if (failure.empty()) {
      if (!unfinished && (acc_.frames == 0 || acc_.last_frame_time < engine_->time())) write_frame();
      if (o_.checkpoint_every > 0 || (unfinished && can_checkpoint())) write_checkpoint();
    }
    files_.flush();
    const char* status = !failure.empty() ? "failed" : signal ? "interrupted" : unfinished ? "stopped" : "ok";
    write_summary(failure, status, std::chrono::duration<double>(Clock::now() - wall_start_).count(), signal);
  }
  /// After an OutputError: the checkpoint written last (atomically) stays readable; say what failed in
  /// summary.json, if it can be written.
  void abandon(const std::string& what) {
    if (!writes()) return;
    try {
      write_summary(what, "failed", std::chrono::duration<double>(Clock::now() - wall_start_).count());
    } catch (const std::exception&) {
    }
  }

  /// A checkpoint of this state, restartable with RunOptions::restart (collective among ranks).
  void write_checkpoint(const std::filesystem::path& file) {
    if (writes()) files_.flush();
    io::write_checkpoint(file, scene_checkpoint::save<Dim>(sc_, *engine_, acc_), comm_);
  }

  SceneEngine<Dim>& engine() { return *engine_; }
  const SceneEngine<Dim>& engine() const { return *engine_; }
  /// Energies and momentum over every rank's particles (the same bits whatever the division).
  Totals<Dim> totals() const {
    const ParticleSet<Dim>& p = engine_->particles();
    const std::array<Real, Dim + 2> sums = engine_->template particle_sum<Dim + 2>([&](std::size_t i) {
      std::array<Real, Dim + 2> v;
      v[0] = 0.5 * p.m[i] * p.v[i].squaredNorm();
      v[1] = engine_->internal_energy(i);
      for (int d = 0; d < Dim; ++d) v[2 + d] = p.m[i] * p.v[i][d];
      return v;
    });
    Totals<Dim> t;
    t.kinetic = sums[0];
    t.strain = sums[1];
    for (int d = 0; d < Dim; ++d) t.momentum[d] = sums[2 + d];
    return t;
  }

  /// The external work and friction dissipation so far.
  const scene_checkpoint::Accumulators& accumulated() const { return acc_; }
  /// Whether the run writes an output folder (RunOptions::out_dir not empty).
  bool writes() const { return !o_.out_dir.empty(); }

 private:
  bool has_check() const { return !sc_.exact_displacement.empty(); }
  /// Whether this run can write a checkpoint: in one process, or among several with parallel HDF5.
  bool can_checkpoint() const { return comm_.size() == 1 || io::collective_checkpoints(); }
  /// A signal on any rank stops every rank after the same step.
  bool interrupted() const { return comm_.max(interrupt_requested()) > 0; }
  /// The [check] error of this step's particles (Wallstedt & Guilkey 2008, Eq. (64)), over every rank.
  void record_error() {
    const ExactFromScene<Dim> exact{&sc_.exact_displacement};
    const ParticleSet<Dim>& p = engine_->particles();
    Real largest = 0;
    const auto delta = [&](std::size_t i) {
      return ((p.x[i] - p.X[i]) - exact.displacement(p.X[i], engine_->time())).norm();
    };
    const std::array<Real, 2> sums = engine_->template particle_sum<2>([&](std::size_t i) {
      const Real d = delta(i);
      largest = std::max(largest, d);
      return std::array<Real, 2>{d, d * d};
    });
    acc_.error.add_sums(comm_.max(largest), sums[0], sums[1], engine_->particle_count());
  }
  Real next_output_time() const { return static_cast<Real>(acc_.frames) * sc_.output_every; }

  void write_history_row() {
    const Totals<Dim> t = totals();
    settling_.observe(engine_->time(), t.kinetic);
    const std::vector<Vec<Dim>> reactions = engine_->reactions();
    const std::vector<PairForces<Dim>> contact = engine_->contact_forces();
    const std::vector<Real> spreads = engine_->spreads();
    if (!root_) return;
    std::ostream& history = files_.history().row();
    history << engine_->steps() << ',' << engine_->time() << ',' << t.kinetic << ',' << t.strain << ','
            << t.kinetic + t.strain << ',' << acc_.external_work;
    for (int d = 0; d < Dim; ++d) history << ',' << t.momentum[d];
    for (const Vec<Dim>& r : reactions)
      for (int d = 0; d < Dim; ++d) history << ',' << r[d];
    for (const std::int64_t n : engine_->counters()) history << ',' << n;
    for (const Real w : spreads) history << ',' << w;
    for (const PairForces<Dim>& c : contact) {
      for (int d = 0; d < Dim; ++d) history << ',' << c.force[d];
      history << ',' << c.normal << ',' << c.tangential;
    }
    if (has_friction(sc_)) history << ',' << acc_.friction_dissipation;
    if (has_outflow(sc_)) {
      const Outflow<Dim>& out = engine_->outflow();
      history << ',' << out.mass << ',' << out.kinetic_energy + out.internal_energy;
      for (int d = 0; d < Dim; ++d) history << ',' << out.momentum[d];
    }
    files_.history().end_row();
  }

  /// Work of gravity, body forces and tractions over the step (force at t^n times the mean of the old and new
  /// velocities) plus the work of the moving constraints (reaction times prescribed velocity); and the energy
  /// friction dissipated on the Coulomb walls (their power over the step times the step).
  void account_work() {
    const Real dt = engine_->time() - previous_time_;
    previous_time_ = engine_->time();
    Real power = engine_->load_power(v_before_);
    const std::vector<Vec<Dim>> walls = engine_->reaction_velocities(engine_->time());
    const std::vector<Vec<Dim>> reactions = engine_->reactions();
    for (std::size_t g = 0; g < walls.size(); ++g) power += reactions[g].dot(walls[g]);
    acc_.external_work += dt * power;
    acc_.friction_dissipation += dt * engine_->friction_power();
  }

  /// One frame of every rank's particles (RunFiles::frame).
  /// The particles as a failure left them (the explicit engine's failed step, the implicit one's last good
  /// state), with the field `failed` (1: a particle that failed) beside the frames' fields.
  void write_failure_frame() {
    std::vector<double> points;
    std::vector<io::PointField> fields;
    frame_fields<Dim>(*engine_, material_laws(sc_), sc_.geometry, sc_.exact_displacement, engine_->time(),
                      points, fields);
    fields.push_back(io::PointField{"failed", 1, engine_->failed_particles()});
    failure_frame_ = files_.failure_frame(points, fields);
  }

  void write_frame() {
    std::vector<double> points;
    std::vector<io::PointField> fields;
    frame_fields<Dim>(*engine_, material_laws(sc_), sc_.geometry, sc_.exact_displacement, engine_->time(),
                      points, fields);
    files_.frame(acc_.frames, engine_->time(), points, fields);
    ++acc_.frames;
    acc_.last_frame_time = engine_->time();
  }

  void write_summary(const std::string& failure, const char* status, double wall, int signal = 0) {
    const std::int64_t particles = engine_->particle_count();
    // After a failure the particle state is not valid: no energies from it.
    const std::optional<Totals<Dim>> t = failure.empty() ? std::optional(totals()) : std::nullopt;
    if (!root_) return;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    nlohmann::json j{{"status", status},
                     {"scene", sc_.file.string()},
                     {"dimension", Dim},
                     {"integrator", sc_.implicit ? std::string_view("implicit") : to_string(sc_.integrator)},
                     {"kernel", to_string(sc_.kernel)},
                     {"steps", engine_->steps()},
                     {"time", engine_->time()},
                     {"end_time", sc_.end_time},
                     {"wall_seconds", wall},
                     {"compute_seconds", compute_seconds_},
                     {"particles", particles},
                     {"frames", acc_.frames},
                     {"ranks", comm_.size()},
                     {"threads", num_threads()},
                     {"memory",
                      {{"estimated_bytes", budget_.memory_bytes},
                       {"peak_bytes", 1024.0 * static_cast<double>(usage.ru_maxrss)}}}};
    if (!failure.empty()) j["failure"] = failure;
    if (!failure_frame_.empty()) j["failure_frame"] = failure_frame_;
    if (signal) j["signal"] = signal_name(signal);
    engine_->summarize(j);
    if (!o_.restart.empty()) j["restarted_from"] = o_.restart.string();
    if (has_check())
      j["error"] = {{"linf", failure.empty() ? acc_.error.linf : 1.0},
                    {"l1", acc_.error.l1()},
                    {"l2", acc_.error.l2()}};
    if (t)
      j["energy"] = {{"kinetic", t->kinetic}, {"strain", t->strain}, {"external_work", acc_.external_work}};
    if (t && sc_.local_damping > 0) j["settled"] = settling_.report();
    if (deforms_half_lengths(sc_.kernel)) j["bounded_domains"] = bounded_.report();
    if (t && has_friction(sc_)) j["energy"]["friction_dissipation"] = acc_.friction_dissipation;
    if (has_outflow(sc_)) {
      const Outflow<Dim>& out = engine_->outflow();
      j["outflow"] = {{"particles", out.particles},
                      {"mass", out.mass},
                      {"momentum", std::vector<double>(out.momentum.data(), out.momentum.data() + Dim)},
                      {"kinetic_energy", out.kinetic_energy},
                      {"internal_energy", out.internal_energy}};
    }
    nlohmann::json history_units = nlohmann::json::object();
    for (const HistoryColumn& column : history_columns<Dim>(sc_, *engine_))
      if (!column.unit.empty()) history_units[column.name] = column.unit;
    const nlohmann::json summary = summary_units(j, per_extent<Dim>(sc_.geometry));
    j["units"] = {{"summary", summary}, {"history", history_units}};
    const BuildInfo& b = build_info();
    j["build"] = {{"version", b.version},   {"commit", b.commit}, {"build_type", b.build_type},
                  {"compiler", b.compiler}, {"flags", b.flags},   {"instruction_set", b.isa},
                  {"mpi", b.mpi},           {"hdf5", b.hdf5}};
    j["overrides"] = sc_.overrides;
    io::write_file_atomically(o_.out_dir / "summary.json", j.dump(2) + '\n');
  }

  /// The per-step files are flushed first, so that a restart from this checkpoint finds every row before it.
  void write_checkpoint() { write_checkpoint(o_.out_dir / "checkpoint.h5"); }

  const Scene& sc_;
  const RunOptions& o_;
  std::unique_ptr<SceneEngine<Dim>> engine_;
  const Communicator& comm_;
  Budget budget_;              // of what is left to run (set by the constructor)
  std::string failure_frame_;  // the last state of a failed run, in the output folder ("": none)
  const bool root_;            // rank 0 writes history.csv, summary.json and the frames' .pvtp and .pvd
  Settling settling_;          // when the kinetic energy of a damped run settled
  BoundedDomains bounded_;     // cpGIMP domains bounded by the stencil's reach
  RunFiles files_{o_.out_dir, comm_};
  scene_checkpoint::Accumulators acc_;  // what a checkpoint carries beside the particles
  Real previous_time_ = 0;
  std::vector<Vec<Dim>> v_before_;  // particle velocities before the step, for the work of the loads
  bool in_step_ = false;  // inside engine_->step(): a failure there may leave the particles half-updated
  double compute_seconds_ = 0;  // inside the time steps, outputs excluded (this run only, not since t = 0)
  Clock::time_point wall_start_ = Clock::now();
};

template <int Dim>
int run_scene_on(const Scene& sc, const RunOptions& o, EngineFactory<Dim> make) {
  return SceneRun<Dim>(sc, o, make).run();
}

}  // namespace mpm

#include "mpm/scene/run.hpp"

#include <sys/resource.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/core/interrupt.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/files.hpp"
#include "mpm/scene/budget.hpp"
#include "mpm/io/vtk.hpp"
#include "progress.hpp"
#include "scene_engines.hpp"
#include "mpm/verification/error_norms.hpp"

namespace mpm {

namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using scene_engines::flat;
using scene_engines::unflat;

/// The scene's [check] block as an exact solution for ErrorNorms.
template <int Dim>
struct ExactFromScene {
  const std::vector<ExpressionPtr>* u;
  Vec<Dim> displacement(const Vec<Dim>& X, Real t) const {
    double vars[Dim + 1];
    for (int d = 0; d < Dim; ++d) vars[d] = X[d];
    vars[Dim] = t;
    return evaluate<Vec<Dim>>(*u, vars);
  }
};

/// Energies and momentum of the particles: kinetic 1/2 m v^2 and the engine's strain (or internal) energy.
template <int Dim>
struct Totals {
  Real kinetic = 0, strain = 0;
  Vec<Dim> momentum = Vec<Dim>::Zero();
};

template <int Dim, class Engine>
class SceneRun {
 public:
  SceneRun(const Scene& sc, const RunOptions& o) : sc_(sc), o_(o), engine_(sc), sim_(engine_.sim()) {
    if (o.restart.empty()) return;
    try {
      restore(io::read_checkpoint(o.restart));
    } catch (const InputError& e) {  // name the option: "checkpoint FILE: not an HDF5 file" alone is unclear
      const std::string what = e.what();
      throw InputError(what.rfind("--restart", 0) == 0 ? what : "--restart: " + what);
    }
  }

  int run() {
    std::cout << describe(estimate_budget(sc_)) << std::endl;
    if (o_.dry_run) return 0;
    const auto wall_start = Clock::now();
    const InterruptHandlers handlers;
    prepare_outputs();
    Progress progress(o_.quiet, sim_.time(), sc_.end_time);
    progress.start_at(sim_.steps());
    std::string failure;
    bool stopped = false;
    int signal = 0;
    try {
      if (sim_.steps() == 0) {
        write_frame();
        write_history_row();
      }
      const std::int64_t stop_at = o_.stop_after > 0 ? sim_.steps() + o_.stop_after : -1;
      try {
        while (sim_.time() < sc_.end_time * (1 - 1e-14) && sim_.steps() != stop_at && !interrupt_requested()) {
          v_before_ = sim_.particles().v;
          const auto step_start = Clock::now();
          in_step_ = true;
          sim_.step(sc_.end_time - sim_.time());
          in_step_ = false;
          compute_seconds_ += std::chrono::duration<double>(Clock::now() - step_start).count();
          account_work();
          if (has_check()) error_.record(sim_.particles(), sim_.time(), ExactFromScene<Dim>{&sc_.exact_displacement});
          write_history_row();
          if (sc_.output_every > 0 && sim_.time() >= next_output_time() * (1 - 1e-12)) write_frame();
          if (o_.checkpoint_every > 0 && sim_.steps() % o_.checkpoint_every == 0) write_checkpoint();
          progress.update(sim_.steps(), sim_.time());
        }
      } catch (const SimulationFailure& e) {
        failure = e.what();
        // The implicit engine fails before it touches the particles: checkpoint the last good state to restart from.
        if (Engine::failure_keeps_state) write_checkpoint();
      } catch (const std::bad_alloc&) {
        failure = "out of memory at step " + std::to_string(sim_.steps() + 1) + " (estimated need " +
                  std::to_string(estimate_budget(sc_).memory_bytes / 1e6) + " MB)";
        // Steps of the explicit engine allocate nothing: memory ran out in the outputs, after a good step.
        if (!in_step_ || Engine::failure_keeps_state) write_checkpoint();
      }
      const bool unfinished = sim_.time() < sc_.end_time * (1 - 1e-14);
      signal = failure.empty() && unfinished ? interrupt_requested() : 0;
      stopped = failure.empty() && unfinished && !signal;
      if (failure.empty()) {
        if (!unfinished && (frames_ == 0 || last_frame_time_ < sim_.time())) write_frame();
        if (o_.checkpoint_every > 0 || unfinished) write_checkpoint();
      }
      flush_history();
    } catch (const OutputError& e) {
      // The checkpoint written last (atomically) stays readable; say what failed, if the summary can be written.
      try {
        write_summary(e.what(), "failed", std::chrono::duration<double>(Clock::now() - wall_start).count());
      } catch (const std::exception&) {
      }
      throw;
    }
    const char* status = !failure.empty() ? "failed" : signal ? "interrupted" : stopped ? "stopped" : "ok";
    write_summary(failure, status, std::chrono::duration<double>(Clock::now() - wall_start).count(), signal);
    if (!failure.empty()) {
      std::cerr << "mpm: simulation failed: " << failure << '\n';
      return exit_simulation_failure;
    }
    if (signal) {
      std::cerr << "mpm: interrupted by " << signal_name(signal) << " after step " << sim_.steps() << ", t = "
                << sim_.time() << " s; continue with --restart " << (o_.out_dir / "checkpoint.h5").string() << '\n';
      return exit_interrupted(signal);
    }
    return 0;
  }

 private:
  bool has_check() const { return !sc_.exact_displacement.empty(); }
  Real next_output_time() const { return static_cast<Real>(frames_) * sc_.output_every; }

  /// Create the output folder; a fresh run clears the outputs of an earlier one, a restart keeps what came
  /// before its checkpoint.
  void prepare_outputs() {
    std::error_code ec;
    fs::create_directories(o_.out_dir, ec);
    if (ec || !fs::is_directory(o_.out_dir))
      throw InputError("--out " + o_.out_dir.string() + ": cannot make the output folder" +
                       (ec ? ": " + ec.message() : " (a file of that name exists)"));
    const fs::path pvd = o_.out_dir / "particles.pvd";
    if (o_.restart.empty()) {
      for (const fs::directory_entry& e : fs::directory_iterator(o_.out_dir)) {
        const std::string name = e.path().filename().string();
        if ((name.rfind("particles_", 0) == 0 && e.path().extension() == ".vtp") || name == "particles.pvd" ||
            name == "history.csv" || name == "summary.json")
          fs::remove(e.path(), ec);
      }
      series_ = io::PvdSeries(pvd);
      history_.open(o_.out_dir / "history.csv");
      if (!history_) throw InputError("--out: cannot write " + (o_.out_dir / "history.csv").string());
      write_history_header();
    } else {
      series_ = fs::exists(pvd) ? io::PvdSeries::resume(pvd, sim_.time()) : io::PvdSeries(pvd);
      frames_ = static_cast<std::int64_t>(series_.entries().size());
      keep_history_until(sim_.steps());
    }
    history_.precision(17);
  }

  void write_history_header() {
    static constexpr const char* axis[] = {"x", "y", "z"};
    history_ << "step,time,kinetic_energy,strain_energy,total_energy,external_work";
    for (int d = 0; d < Dim; ++d) history_ << ",momentum_" << axis[d];
    for (const std::string& name : engine_.reaction_names())
      for (int d = 0; d < Dim; ++d) history_ << ",reaction_" << name << "_" << axis[d];
    history_ << '\n';
  }

  /// After a restart: keep the header and the rows up to the checkpoint's step, then append.
  void keep_history_until(std::int64_t step) {
    const fs::path file = o_.out_dir / "history.csv";
    std::vector<std::string> kept;
    std::ifstream is(file);
    for (std::string line; std::getline(is, line);) {
      if (!kept.empty() && std::stoll(line.substr(0, line.find(','))) > step) break;
      kept.push_back(line);
    }
    is.close();
    history_.open(file, std::ios::trunc);
    if (!history_) throw InputError("--out: cannot write " + file.string());
    if (kept.empty()) write_history_header();
    for (const std::string& line : kept) history_ << line << '\n';
  }

  void write_history_row() {
    const Totals<Dim> t = totals();
    history_ << sim_.steps() << ',' << sim_.time() << ',' << t.kinetic << ',' << t.strain << ','
             << t.kinetic + t.strain << ',' << external_work_;
    for (int d = 0; d < Dim; ++d) history_ << ',' << t.momentum[d];
    for (const Vec<Dim>& r : engine_.reactions())
      for (int d = 0; d < Dim; ++d) history_ << ',' << r[d];
    history_ << '\n';
    if (!history_) history_failed();
  }

  void flush_history() {
    history_.flush();
    if (!history_) history_failed();
  }

  [[noreturn]] void history_failed() const {
    throw OutputError("cannot write " + (o_.out_dir / "history.csv").string() + ": " +
                      (errno ? std::strerror(errno) : "write failed"));
  }

  /// Work of gravity, body forces and tractions over the step (force at t^n times the mean of the old and new
  /// velocities) plus the work of the moving constraints (reaction times prescribed velocity).
  void account_work() {
    const std::vector<Vec<Dim>>& v_before = v_before_;
    const ParticleSet<Dim>& p = sim_.particles();
    const Real dt = sim_.time() - previous_time_;
    previous_time_ = sim_.time();
    Real power = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      power += p.m[i] * engine_.load_acceleration(i).dot(0.5 * (v_before[i] + p.v[i]));
    const std::vector<Vec<Dim>> walls = engine_.reaction_velocities(sim_.time());
    const std::vector<Vec<Dim>> reactions = engine_.reactions();
    for (std::size_t g = 0; g < walls.size(); ++g) power += reactions[g].dot(walls[g]);
    external_work_ += dt * power;
  }

  void write_frame() {
    const ParticleSet<Dim>& p = sim_.particles();
    const std::size_t n = p.size();
    std::vector<double> points(3 * n, 0.0);
    io::PointField velocity{"velocity", 3, std::vector<double>(3 * n, 0.0)};
    io::PointField displacement{"displacement", 3, std::vector<double>(3 * n, 0.0)};
    io::PointField stress{"stress", 6, std::vector<double>(6 * n, 0.0)};
    io::PointField deformation{"F", 9, std::vector<double>(9 * n, 0.0)};
    io::PointField J{"J", 1, {}}, volume{"volume", 1, {}}, mass{"mass", 1, {}}, material{"material", 1, {}};
    io::PointField error{"error", 1, {}};
    for (std::size_t i = 0; i < n; ++i) {
      const Real Ji = p.F[i].determinant();
      for (int d = 0; d < Dim; ++d) {
        points[3 * i + d] = p.x[i][d];
        velocity.values[3 * i + d] = p.v[i][d];
        displacement.values[3 * i + d] = p.x[i][d] - p.X[i][d];
      }
      engine_.stress(i, &stress.values[6 * i]);
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
          deformation.values[9 * i + 3 * a + c] = (a < Dim && c < Dim) ? p.F[i](a, c) : (a == c ? 1.0 : 0.0);
      J.values.push_back(Ji);
      volume.values.push_back(p.V[i]);
      mass.values.push_back(p.m[i]);
      material.values.push_back(p.material[i]);
      if (has_check())
        error.values.push_back(
            ((p.x[i] - p.X[i]) - ExactFromScene<Dim>{&sc_.exact_displacement}.displacement(p.X[i], sim_.time())).norm());
    }
    std::vector<io::PointField> fields;
    for (io::PointField* f : {&velocity, &displacement, &stress, &deformation, &J, &volume, &mass, &material})
      fields.push_back(std::move(*f));
    if (has_check()) fields.push_back(std::move(error));
    engine_.add_fields(fields);
    std::ostringstream name;
    name << "particles_" << std::setw(4) << std::setfill('0') << frames_ << ".vtp";
    io::write_vtp(o_.out_dir / name.str(), points, fields);
    series_.add(sim_.time(), name.str());
    ++frames_;
    last_frame_time_ = sim_.time();
  }

  void write_summary(const std::string& failure, const char* status, double wall, int signal = 0) {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    nlohmann::json j{{"status", status},
                     {"scene", sc_.file.string()},
                     {"dimension", Dim},
                     {"integrator", sc_.implicit ? std::string_view("implicit") : to_string(sc_.integrator)},
                     {"kernel", to_string(sc_.kernel)},
                     {"steps", sim_.steps()},
                     {"time", sim_.time()},
                     {"end_time", sc_.end_time},
                     {"wall_seconds", wall},
                     {"compute_seconds", compute_seconds_},
                     {"particles", sim_.particles().size()},
                     {"frames", frames_},
                     {"threads", num_threads()},
                     {"memory", {{"estimated_bytes", estimate_budget(sc_).memory_bytes},
                                 {"peak_bytes", 1024.0 * static_cast<double>(usage.ru_maxrss)}}}};
    if (!failure.empty()) j["failure"] = failure;
    if (signal) j["signal"] = signal_name(signal);
    engine_.summarize(j);
    if (!o_.restart.empty()) j["restarted_from"] = o_.restart.string();
    if (has_check())
      j["error"] = {{"linf", failure.empty() ? error_.linf : 1.0}, {"l1", error_.l1()}, {"l2", error_.l2()}};
    if (failure.empty()) {  // after a failure the particle state is not valid: no energies from it
      const Totals<Dim> t = totals();
      j["energy"] = {{"kinetic", t.kinetic}, {"strain", t.strain}, {"external_work", external_work_}};
    }
    io::write_file_atomically(o_.out_dir / "summary.json", j.dump(2) + '\n');
  }

  // Checkpoints: the particle arrays, the clock and the run's accumulators, bit for bit.
  void write_checkpoint() {
    const ParticleSet<Dim>& p = sim_.particles();
    io::CheckpointData c;
    c.texts["scene"] = sc_.text;
    c.integer_scalars = {{"dim", Dim}, {"particles", static_cast<std::int64_t>(p.size())}, {"steps", sim_.steps()},
                         {"frames", frames_}, {"error_samples", error_.samples}};
    c.real_scalars = {{"time", sim_.time()}, {"external_work", external_work_}, {"last_frame_time", last_frame_time_},
                      {"error_linf", error_.linf}, {"error_sum", error_.sum}, {"error_sum_sq", error_.sum_sq}};
    c.reals = {{"x", flat(p.x)}, {"X", flat(p.X)}, {"v", flat(p.v)}, {"F", flat(p.F)}, {"m", p.m}, {"V0", p.V0},
               {"l0", flat(p.l0)}, {"l", flat(p.l)}};
    c.integers["material"] = std::vector<std::int64_t>(p.material.begin(), p.material.end());
    engine_.save(c);
    io::write_checkpoint(o_.out_dir / "checkpoint.h5", c);
  }

  void restore(const io::CheckpointData& c) {
    const std::string where = "--restart " + o_.restart.string();
    auto scalar = [&](const auto& map, const std::string& key) -> const auto& {
      auto it = map.find(key);
      if (it == map.end()) throw InputError(where + ": not a checkpoint of a scene run (no '" + key + "')");
      return it->second;
    };
    ParticleSet<Dim>& p = sim_.particles();
    if (scalar(c.integer_scalars, "dim") != Dim || scalar(c.integer_scalars, "particles") != static_cast<std::int64_t>(p.size()))
      throw InputError(where + ": the checkpoint holds a different scene (dimension or particle count differ)");
    auto array = [&](const std::string& key) -> const std::vector<double>& { return scalar(c.reals, key); };
    unflat(array("x"), p.x, "x");
    unflat(array("X"), p.X, "X");
    unflat(array("v"), p.v, "v");
    unflat(array("F"), p.F, "F");
    unflat(array("l0"), p.l0, "l0");
    unflat(array("l"), p.l, "l");
    p.m = array("m");
    p.V0 = array("V0");
    const std::vector<std::int64_t>& mat = scalar(c.integers, "material");
    for (std::size_t i = 0; i < p.size(); ++i) p.material[i] = static_cast<std::uint16_t>(mat.at(i));
    engine_.load(c, where);
    previous_time_ = sim_.time();
    external_work_ = scalar(c.real_scalars, "external_work");
    last_frame_time_ = scalar(c.real_scalars, "last_frame_time");
    error_.linf = scalar(c.real_scalars, "error_linf");
    error_.sum = scalar(c.real_scalars, "error_sum");
    error_.sum_sq = scalar(c.real_scalars, "error_sum_sq");
    error_.samples = scalar(c.integer_scalars, "error_samples");
  }

  Totals<Dim> totals() const {
    const ParticleSet<Dim>& p = sim_.particles();
    Totals<Dim> t;
    for (std::size_t i = 0; i < p.size(); ++i) {
      t.kinetic += 0.5 * p.m[i] * p.v[i].squaredNorm();
      t.momentum += p.m[i] * p.v[i];
    }
    t.strain = engine_.strain_energy();
    return t;
  }

  const Scene& sc_;
  const RunOptions& o_;
  Engine engine_;
  decltype(engine_.sim())& sim_;
  io::PvdSeries series_{""};
  std::ofstream history_;
  std::int64_t frames_ = 0;
  Real last_frame_time_ = -1;
  Real previous_time_ = 0;
  Real external_work_ = 0;
  std::vector<Vec<Dim>> v_before_;  // particle velocities before the step, for the work of the loads
  bool in_step_ = false;             // inside sim_.step(): a failure there may leave the particles half-updated
  double compute_seconds_ = 0;  // inside the time steps, outputs excluded (this run only, not since t = 0)
  ErrorNorms error_;
};

template <int Dim>
int run_in(const Scene& sc, const RunOptions& o) {
  return with_kernel(sc.kernel, [&]<class Kernel>() {
    if constexpr (Dim >= 2)
      if (sc.implicit) return SceneRun<Dim, scene_engines::Implicit<Dim, Kernel>>(sc, o).run();
    return SceneRun<Dim, scene_engines::Explicit<Dim, Kernel>>(sc, o).run();
  });
}
}  // namespace

int run_scene(const Scene& scene, const RunOptions& options) {
  set_num_threads(options.threads > 0 ? options.threads : scene.threads);
  if (options.checkpoint_every < 0) throw InputError("--checkpoint-every: expected a non-negative step count");
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

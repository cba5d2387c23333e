#include "mpm/scene/run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/vtk.hpp"
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

/// Progress on stderr for runs longer than about two seconds: percent, step, time, steps per second, ETA.
class Progress {
 public:
  Progress(bool quiet, Real t0, Real t_end) : quiet_(quiet), t0_(t0), t_end_(t_end), start_(Clock::now()), last_(start_) {}
  void update(std::int64_t step, Real t) {
    if (quiet_) return;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (elapsed < 2 || std::chrono::duration<double>(now - last_).count() < 0.5) return;
    last_ = now;
    const double fraction = (t - t0_) / (t_end_ - t0_);
    const double rate = static_cast<double>(step - first_step_) / elapsed;
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    std::fprintf(stderr, "\r%5.1f%%  step %lld  t = %.6g s  %.0f steps/s  ETA %.0f s   ", 100 * t / t_end_,
                 static_cast<long long>(step), t, rate, eta);
    printed_ = true;
  }
  void start_at(std::int64_t step) { first_step_ = step; }
  ~Progress() {
    if (printed_) std::fprintf(stderr, "\n");
  }

 private:
  bool quiet_;
  Real t0_, t_end_;
  Clock::time_point start_, last_;
  std::int64_t first_step_ = 0;
  bool printed_ = false;
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
    const auto wall_start = Clock::now();
    prepare_outputs();
    Progress progress(o_.quiet, sim_.time(), sc_.end_time);
    progress.start_at(sim_.steps());
    if (sim_.steps() == 0) {
      write_frame();
      write_history_row();
    }
    std::string failure;
    const std::int64_t stop_at = o_.stop_after > 0 ? sim_.steps() + o_.stop_after : -1;
    try {
      while (sim_.time() < sc_.end_time * (1 - 1e-14) && sim_.steps() != stop_at) {
        const std::vector<Vec<Dim>> v_before = sim_.particles().v;
        const auto step_start = Clock::now();
        sim_.step(sc_.end_time - sim_.time());
        compute_seconds_ += std::chrono::duration<double>(Clock::now() - step_start).count();
        account_work(v_before);
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
    }
    const bool stopped = failure.empty() && sim_.steps() == stop_at && sim_.time() < sc_.end_time * (1 - 1e-14);
    if (failure.empty()) {
      if (!stopped && (frames_ == 0 || last_frame_time_ < sim_.time())) write_frame();
      if (o_.checkpoint_every > 0 || stopped) write_checkpoint();
    }
    history_.flush();
    write_summary(failure, stopped, std::chrono::duration<double>(Clock::now() - wall_start).count());
    if (!failure.empty()) {
      std::cerr << "mpm: simulation failed: " << failure << '\n';
      return exit_simulation_failure;
    }
    return 0;
  }

 private:
  bool has_check() const { return !sc_.exact_displacement.empty(); }
  Real next_output_time() const { return static_cast<Real>(frames_) * sc_.output_every; }

  /// Create the output folder; a fresh run clears the outputs of an earlier one, a restart keeps what came
  /// before its checkpoint.
  void prepare_outputs() {
    fs::create_directories(o_.out_dir);
    const fs::path pvd = o_.out_dir / "particles.pvd";
    if (o_.restart.empty()) {
      for (const fs::directory_entry& e : fs::directory_iterator(o_.out_dir)) {
        const std::string name = e.path().filename().string();
        if ((name.rfind("particles_", 0) == 0 && e.path().extension() == ".vtp") || name == "particles.pvd" ||
            name == "history.csv" || name == "summary.json")
          fs::remove(e.path());
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
  }

  /// Work of gravity, body forces and tractions over the step (force at t^n times the mean of the old and new
  /// velocities) plus the work of the moving constraints (reaction times prescribed velocity).
  void account_work(const std::vector<Vec<Dim>>& v_before) {
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
    std::vector<io::PointField> fields{velocity, displacement, stress, deformation, J, volume, mass, material};
    if (has_check()) fields.push_back(error);
    engine_.add_fields(fields);
    std::ostringstream name;
    name << "particles_" << std::setw(4) << std::setfill('0') << frames_ << ".vtp";
    io::write_vtp(o_.out_dir / name.str(), points, fields);
    series_.add(sim_.time(), name.str());
    ++frames_;
    last_frame_time_ = sim_.time();
  }

  void write_summary(const std::string& failure, bool stopped, double wall) {
    nlohmann::json j{{"status", !failure.empty() ? "failed" : (stopped ? "stopped" : "ok")},
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
                     {"threads", num_threads()}};
    if (!failure.empty()) j["failure"] = failure;
    engine_.summarize(j);
    if (!o_.restart.empty()) j["restarted_from"] = o_.restart.string();
    if (has_check())
      j["error"] = {{"linf", failure.empty() ? error_.linf : 1.0}, {"l1", error_.l1()}, {"l2", error_.l2()}};
    if (failure.empty()) {  // after a failure the particle state is not valid: no energies from it
      const Totals<Dim> t = totals();
      j["energy"] = {{"kinetic", t.kinetic}, {"strain", t.strain}, {"external_work", external_work_}};
    }
    std::ofstream(o_.out_dir / "summary.json") << j.dump(2) << '\n';
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

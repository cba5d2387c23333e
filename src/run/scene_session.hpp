#pragma once
// A Session (mpm/run/session.hpp) over one engine's SceneRun: the Python module's runs, stepped one call at
// a time, with read-only views of the particles and the grid. Instantiated once per engine, dimension and
// kernel (scene_entry.hpp).
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/run/session.hpp"
#include "run_arrays.hpp"
#include "scene_entry.hpp"
#include "scene_run.hpp"

namespace mpm {

namespace scene_views {
/// A view of `rows` records of `stride` bytes, `components` Reals each from `first` (a scalar field: one
/// axis).
inline FieldArray view(std::string name, const void* first, std::size_t rows, std::ptrdiff_t stride,
                       int components) {
  FieldArray f{std::move(name), 'f', sizeof(Real), {rows}, {stride}, first, nullptr};
  if (components > 1) {
    f.shape.push_back(static_cast<std::size_t>(components));
    f.strides.push_back(sizeof(Real));
  }
  return f;
}
/// A copy of `values`, rows x components.
inline FieldArray copy(std::string name, std::vector<double> values, int components) {
  auto owned = std::make_shared<std::vector<double>>(std::move(values));
  const std::size_t rows = owned->size() / static_cast<std::size_t>(components);
  FieldArray f = view(std::move(name), owned->data(), rows,
                      components * static_cast<std::ptrdiff_t>(sizeof(double)), components);
  f.owned = std::move(owned);
  return f;
}
template <class T>
FieldArray integers(std::string name, const std::vector<T>& a) {
  return {std::move(name), std::is_signed_v<T> ? 'i' : 'u', sizeof(T), {a.size()}, {sizeof(T)}, a.data(),
          nullptr};
}
}  // namespace scene_views

template <int Dim>
class SceneSession final : public Session {
 public:
  SceneSession(const Scene& sc, const RunOptions& o, EngineFactory<Dim> make)
      : scene_(sc), options_(o), run_(scene_, options_, make) {
    run_.open();
  }
  ~SceneSession() override {
    try {
      close();
    } catch (const std::exception&) {  // a destructor cannot report: close() explicitly to see output errors
    }
  }

  int dim() const override { return Dim; }
  double time() const override { return engine().time(); }
  std::int64_t steps() const override { return engine().steps(); }
  double end_time() const override { return scene_.end_time; }
  double next_dt() const override { return engine().next_dt(); }

  void step() override {
    if (failure_.size()) throw SimulationFailure("the run failed earlier: " + failure_);
    if (run_.at_end())
      throw InputError("step: the scene ended at end_time = " + std::to_string(scene_.end_time) + " s");
    refuse_if_closed("step");
    try {
      run_.advance();
    } catch (const SimulationFailure& e) {
      failure_ = run_.failed(e.what());
      throw;
    } catch (const std::bad_alloc&) {
      failure_ = run_.out_of_memory();
      throw;
    }
  }

  void close() override {
    if (closed_) return;
    closed_ = true;
    run_.close(failure_);
  }

  void checkpoint(const std::filesystem::path& file) override {
    refuse_if_closed("checkpoint");
    run_.write_checkpoint(file);
  }

  SessionTotals totals() const override {
    const Totals<Dim> t = run_.totals();
    const scene_checkpoint::Accumulators& a = run_.accumulated();
    return {t.kinetic, t.strain, a.external_work, a.friction_dissipation,
            std::vector<double>(t.momentum.data(), t.momentum.data() + Dim)};
  }

  std::vector<std::string> reaction_names() const override { return engine().reaction_names(); }
  std::vector<double> reactions() const override { return scene_engines::flat(engine().reactions()); }

  std::vector<std::string> particle_field_names() const override {
    std::vector<std::string> names{"x", "X",      "velocity", "displacement", "stress", "F",
                                   "J", "volume", "mass",     "material",     "id"};
    if (!scene().exact_displacement.empty()) names.push_back("error");
    for (const io::PointField& f : engine_fields()) names.push_back(f.name);
    return names;
  }

  FieldArray particle_field(const std::string& name) const override {
    const ParticleSet<Dim>& p = engine().particles();
    const std::size_t n = p.size();
    constexpr auto vec = static_cast<std::ptrdiff_t>(sizeof(Vec<Dim>));
    const auto per_particle = [&](int components, auto&& value) {
      std::vector<double> out(n * static_cast<std::size_t>(components));
      for (std::size_t i = 0; i < n; ++i) value(i, &out[i * static_cast<std::size_t>(components)]);
      return scene_views::copy(name, std::move(out), components);
    };
    if (name == "x") return scene_views::view(name, p.x.data(), n, vec, Dim);
    if (name == "X") return scene_views::view(name, p.X.data(), n, vec, Dim);
    if (name == "velocity") return scene_views::view(name, p.v.data(), n, vec, Dim);
    if (name == "volume") return scene_views::view(name, p.V.data(), n, sizeof(Real), 1);
    if (name == "mass") return scene_views::view(name, p.m.data(), n, sizeof(Real), 1);
    if (name == "material") return scene_views::integers(name, p.material);
    if (name == "id") return scene_views::integers(name, p.id);
    if (name == "F")  // F(a, c) of the column-major Dim x Dim matrices: rows a, then columns c
      return {name,
              'f',
              sizeof(Real),
              {n, Dim, Dim},
              {static_cast<std::ptrdiff_t>(sizeof(Mat<Dim>)), sizeof(Real), Dim * sizeof(Real)},
              p.F.data(),
              nullptr};
    if (name == "displacement")
      return per_particle(Dim, [&](std::size_t i, double* u) {
        for (int d = 0; d < Dim; ++d) u[d] = p.x[i][d] - p.X[i][d];
      });
    if (name == "stress") return per_particle(6, [&](std::size_t i, double* s) { engine().stress(i, s); });
    if (name == "J") return per_particle(1, [&](std::size_t i, double* J) { *J = p.F[i].determinant(); });
    if (name == "error" && !scene().exact_displacement.empty()) {  // Wallstedt & Guilkey 2008, Eq. (64)
      const ExactFromScene<Dim> exact{&scene().exact_displacement};
      return per_particle(1, [&](std::size_t i, double* e) {
        *e = ((p.x[i] - p.X[i]) - exact.displacement(p.X[i], engine().time())).norm();
      });
    }
    for (io::PointField& f : engine_fields())
      if (f.name == name) return scene_views::copy(name, std::move(f.values), f.components);
    throw InputError("particles: no field '" + name + "'");
  }

  std::vector<FieldArray> grid_fields() const override {
    const Grid<Dim>& g = engine().grid();
    const std::size_t n = g.size();
    std::vector<double> position(n * Dim);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec<Dim> x = g.geometry.position(g.geometry.coords(static_cast<std::ptrdiff_t>(k)));
      for (int d = 0; d < Dim; ++d) position[k * Dim + d] = x[d];
    }
    constexpr auto node = static_cast<std::ptrdiff_t>(sizeof(GridNode<Dim>));
    return {scene_views::copy("position", std::move(position), Dim),
            scene_views::view("mass", &g.nodes.data()->m, n, node, 1),
            scene_views::view("velocity", g.nodes.data()->v.data(), n, node, Dim)};
  }

  std::vector<std::size_t> grid_shape() const override {
    std::vector<std::size_t> shape;
    for (int d = 0; d < Dim; ++d)
      shape.push_back(static_cast<std::size_t>(engine().grid().geometry.nodes_along(d)));
    return shape;
  }

  void set_velocities(const double* v, std::size_t count) override {
    refuse_if_closed("set_velocities");
    if (count != engine().particles().size() * Dim)
      throw InputError("velocities: expected " + std::to_string(engine().particles().size()) + " x " +
                       std::to_string(Dim) + " values, got " + std::to_string(count));
    std::vector<Vec<Dim>> given(count / Dim);
    for (std::size_t i = 0; i < given.size(); ++i)
      for (int d = 0; d < Dim; ++d) given[i][d] = v[i * Dim + d];
    check_initial_speed(scene_, "set_velocities", fastest_speed<Dim>(given));
    // Through the mutable particles: the explicit engine then recomputes its stencils before the next step.
    run_.engine().particles().v = std::move(given);
  }

 private:
  /// After close() the outputs are finished: the state may be read, not advanced or written.
  void refuse_if_closed(const std::string& call) const {
    if (closed_)
      throw InputError(call +
                       ": the simulation is closed (its outputs are finished); open a new one, with restart "
                       "from a checkpoint to go on");
  }
  const SceneEngine<Dim>& engine() const { return run_.engine(); }
  const Scene& scene() const { return scene_; }
  /// The engine's own fields, as the frames write them (the rate-form state, the contact field).
  std::vector<io::PointField> engine_fields() const {
    std::vector<io::PointField> fields;
    engine().add_fields(fields);
    return fields;
  }

  const Scene scene_;  // SceneRun refers to it and to options_
  const RunOptions options_;
  SceneRun<Dim> run_;
  std::string failure_;
  bool closed_ = false;
};

template <int Dim>
std::unique_ptr<Session> open_session_on(const Scene& sc, const RunOptions& o, EngineFactory<Dim> make) {
  return std::make_unique<SceneSession<Dim>>(sc, o, make);
}

}  // namespace mpm

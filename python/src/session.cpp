// mpm._core.Session: one scene run driven from Python. It steps without the GIL, in slices of about a fifth
// of a second, and between slices lets Python handle its signals: Ctrl-C (KeyboardInterrupt) stops a run
// after a whole step.
#include "mpm/run/session.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "mpm/core/errors.hpp"

namespace py = pybind11;

namespace mpm::python {

namespace {

/// A Session that one Python call at a time may use: the arrays it lends are read while no step runs.
struct PySession {
  std::unique_ptr<Session> run;
  bool busy = false;  // a step runs (without the GIL): another thread's call must wait for it

  Session& use() {
    if (busy) throw std::runtime_error("Simulation: a step is running in another thread");
    return *run;
  }
  /// Steps while `more()` says so, without the GIL; returns after `seconds` of wall time (and at least one
  /// step) so that the caller can look at its signals. Returns the steps taken.
  template <class More>
  std::int64_t steps_while(More&& more, double seconds) {
    Session& s = use();
    busy = true;
    std::int64_t taken = 0;
    std::exception_ptr error;
    {
      py::gil_scoped_release released;
      const auto start = std::chrono::steady_clock::now();
      try {
        do {
          s.step();
          ++taken;
        } while (more() &&
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds);
      } catch (...) {
        error = std::current_exception();
      }
    }
    busy = false;
    if (error) std::rethrow_exception(error);
    return taken;
  }
};

/// A read-only NumPy array of a field: a view whose base is the session object (which outlives it), or a
/// copy.
py::array to_numpy(const FieldArray& f, py::handle owner) {
  const py::dtype type(std::string(1, f.kind == 'f' ? 'f' : f.kind) + std::to_string(f.item_size));
  py::object base;
  if (f.owned) {
    auto* keep = new std::shared_ptr<std::vector<double>>(f.owned);
    base = py::capsule(keep, [](void* p) { delete static_cast<std::shared_ptr<std::vector<double>>*>(p); });
  } else {
    base = py::reinterpret_borrow<py::object>(owner);
  }
  py::array a(type, f.shape, f.strides, f.data, base);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace

void bind_session(py::module_& m) {
  py::class_<PySession>(m, "Session")
      .def(py::init([](const Scene& scene, int threads, std::optional<std::filesystem::path> out,
                       std::optional<std::filesystem::path> restart, std::int64_t checkpoint_every) {
             RunOptions o;
             o.out_dir = out.value_or("");
             o.threads = threads;
             o.restart = restart.value_or("");
             o.checkpoint_every = checkpoint_every;
             if (checkpoint_every > 0 && !out)
               throw InputError(
                   "checkpoint_every: the checkpoints go into the output folder: give out as well");
             auto s = std::make_unique<PySession>();
             s->run = open_session(scene, o);
             return s;
           }),
           py::arg("scene"), py::arg("threads") = 0, py::arg("out") = py::none(),
           py::arg("restart") = py::none(), py::arg("checkpoint_every") = 0)
      .def_property_readonly("dim", [](PySession& s) { return s.use().dim(); })
      .def_property_readonly("time", [](PySession& s) { return s.use().time(); })
      .def_property_readonly("steps", [](PySession& s) { return s.use().steps(); })
      .def_property_readonly("end_time", [](PySession& s) { return s.use().end_time(); })
      .def_property_readonly("next_dt", [](PySession& s) { return s.use().next_dt(); })
      .def("step", [](PySession& s) { s.steps_while([] { return false; }, 0); })
      .def(
          "advance",
          [](PySession& s, double until, std::int64_t max_steps, double seconds) {
            Session& run = s.use();
            // Whole steps only: the last may pass `until` (a step is never shortened but by the end time).
            const auto more = [&, first = run.steps()] {
              return run.time() < until * (1 - 1e-14) && run.time() < run.end_time() * (1 - 1e-14) &&
                     (max_steps <= 0 || run.steps() - first < max_steps);
            };
            if (!more()) return std::int64_t{0};
            const std::int64_t taken = s.steps_while(more, seconds);
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            return taken;
          },
          py::arg("until"), py::arg("max_steps") = 0, py::arg("seconds") = 0.2)
      .def("close", [](PySession& s) { s.use().close(); })
      .def("checkpoint", [](PySession& s, const std::filesystem::path& file) { s.use().checkpoint(file); })
      .def("totals",
           [](PySession& s) {
             const SessionTotals t = s.use().totals();
             py::dict d;
             d["kinetic"] = t.kinetic;
             d["strain"] = t.strain;
             d["total"] = t.kinetic + t.strain;
             d["external_work"] = t.external_work;
             d["friction_dissipation"] = t.friction_dissipation;
             d["momentum"] = py::array(static_cast<py::ssize_t>(t.momentum.size()), t.momentum.data());
             return d;
           })
      .def("reactions",
           [](PySession& s) {
             const std::vector<std::string> names = s.use().reaction_names();
             const std::vector<double> forces = s.use().reactions();
             const std::size_t dim = static_cast<std::size_t>(s.use().dim());
             py::dict d;
             for (std::size_t k = 0; k < names.size(); ++k)
               d[py::str(names[k])] = py::array(static_cast<py::ssize_t>(dim), forces.data() + k * dim);
             return d;
           })
      .def("particle_field_names", [](PySession& s) { return s.use().particle_field_names(); })
      .def("particle_field",
           [](py::object self, const std::string& name) {
             return to_numpy(self.cast<PySession&>().use().particle_field(name), self);
           })
      .def("grid_fields",
           [](py::object self) {
             py::dict d;
             for (const FieldArray& f : self.cast<PySession&>().use().grid_fields())
               d[py::str(f.name)] = to_numpy(f, self);
             return d;
           })
      .def("grid_shape", [](PySession& s) { return s.use().grid_shape(); })
      .def("set_velocities",
           [](PySession& s, const py::array_t<double, py::array::c_style | py::array::forcecast>& v) {
             s.use().set_velocities(v.data(), static_cast<std::size_t>(v.size()));
           });
}

}  // namespace mpm::python

// mpm._core: the library's scene, run and study facades for Python (docs/python.md). The package python/mpm
// wraps it.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "mpm/core/build_info.hpp"
#include "mpm/core/errors.hpp"

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  m.doc() = "The compiled part of the mpm package: use the names the package mpm exports.";
  m.attr("__version__") = mpm::build_info().version;
  m.attr("build") = mpm::build_info_text();
  // Bad input is a ValueError with the one-line message `mpm` prints before exiting with status 2; a
  // numerical failure (exit status 1) is mpm.SimulationFailure, a RuntimeError; an output that cannot be
  // written is mpm.OutputError, an OSError.
  static py::exception<mpm::SimulationFailure> failure(m, "SimulationFailure", PyExc_RuntimeError);
  static py::exception<mpm::OutputError> output(m, "OutputError", PyExc_OSError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const mpm::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const mpm::SimulationFailure& e) {
      failure(e.what());
    } catch (const mpm::OutputError& e) {
      output(e.what());
    }
  });
  mpm::python::bind_scene(m);
  mpm::python::bind_session(m);
  mpm::python::bind_study(m);
}

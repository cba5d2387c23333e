// mpm._core.verify and mpm._core.converge: the manufactured-solution studies of `mpm verify` and `mpm
// converge`, their rows as JSON text (the package turns them into dicts).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/verification/report.hpp"

namespace py = pybind11;

namespace mpm::python {

namespace {
/// The request from the package's keywords: names as strings, numbers by their VerifyOptions names.
StudyRequest request(const std::string& which, const py::dict& kw) {
  StudyRequest r;
  r.case_name = which;
  VerifyOptions& o = r.options;
  for (auto [k, v] : kw) {
    const std::string key = py::str(k);
    std::string* name = key == "kernel"                     ? &r.kernel
                        : key == "transfer"                 ? &r.transfer
                        : key == "integrator"               ? &r.integrator
                        : key == "cfl_speed"                ? &r.cfl_speed
                        : key == "error"                    ? &r.error
                        : key == "start"                    ? &r.start
                        : key == "constrained_acceleration" ? &r.constrained_acceleration
                                                            : nullptr;
    try {
      if (name)
        *name = v.cast<std::string>();
      else if (key == "dim")
        o.dim = v.cast<int>();
      else if (key == "cells")
        o.cells = v.cast<int>();
      else if (key == "ppc")
        o.ppc = v.cast<int>();
      else if (key == "cfl")
        o.cfl = v.cast<double>();
      else if (key == "theta")
        o.theta = v.cast<double>();
      else if (key == "amplitude")
        o.amplitude = v.cast<double>();
      else if (key == "nu")
        o.poisson = v.cast<double>();
      else if (key == "end_time")
        o.end_time = v.cast<double>();
      else
        throw InputError(
            key +
            ": not an option of the studies (kernel, transfer, integrator, cfl_speed, error, start, "
            "constrained_acceleration, dim, cells, ppc, cfl, theta, amplitude, nu, end_time)");
    } catch (const py::cast_error&) {
      const bool integer = key == "dim" || key == "cells" || key == "ppc";
      if (integer && py::hasattr(v, "__index__"))
        throw InputError(key + ": expected an integer of at most 2147483647, got " + short_repr(v));
      throw InputError(key + ": expected " +
                       (name      ? "a name"
                        : integer ? "an integer"
                                  : "a number") +
                       ", got " + short_repr(v));
    }
  }
  return r;
}
}  // namespace

void bind_study(py::module_& m) {
  m.def(
      "verify",
      [](const std::string& which, int threads, const py::kwargs& kw) {
        StudyRequest r = request(which, kw);
        const VerifyCase c = r.resolve();
        set_num_threads(threads);
        VerifyResult result;
        {
          py::gil_scoped_release released;
          result = verify(c, r.options);
        }
        return study_row(c, r.options, result).dump();
      },
      py::arg("case"), py::arg("threads") = 0);
  m.def(
      "converge",
      [](const std::string& which, const std::string& vary, const std::vector<double>& values,
         const std::string& series, int threads, const py::kwargs& kw) {
        if (vary != "cells" && vary != "cfl")
          throw InputError("--vary: expected cells or cfl, got '" + vary + "'");
        if (values.size() < 2) throw InputError("--values: expected at least two comma-separated values");
        StudyRequest r = request(which, kw);
        const VerifyCase c = r.resolve();
        set_num_threads(threads);
        const std::vector<StudySeries> s =
            series.empty() ? std::vector<StudySeries>{{r.options.kernel, r.integrator, r.options.transfer}}
                           : parse_series(series, r.options.transfer);
        std::string rows;
        {
          py::gil_scoped_release released;
          rows = convergence_rows(c, r.options, s, vary == "cells", values).dump();
        }
        return rows;
      },
      py::arg("case"), py::arg("vary"), py::arg("values"), py::arg("series") = "", py::arg("threads") = 0);
}

}  // namespace mpm::python

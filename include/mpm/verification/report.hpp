#pragma once
/// The manufactured-solution studies by name, as `mpm verify`, `mpm converge` and the Python module take and
/// report them: one set of names, one JSON row per run, one sweep with its observed orders.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mpm/verification/study.hpp"

namespace mpm {

/// A study's options by name (the command's options, the Python keywords), and its numbers.
struct StudyRequest {
  std::string case_name;
  std::string kernel = "cpgimp";
  std::string transfer = "flip";
  std::string integrator = "cd";
  std::string cfl_speed = "particles";
  std::string error = "particles";
  std::string start = "halve";
  std::string constrained_acceleration = "zero";
  VerifyOptions options;  ///< the numbers (cells, ppc, cfl, ...); the names above replace its enumerations
  /// Resolve the names into `options` and validate them; InputError names the command's option
  /// ("--cfl-speed").
  VerifyCase resolve();
};

/// One run's row: the case, its options, dt, steps and the error norms; "failure" when it failed.
nlohmann::json study_row(VerifyCase c, const VerifyOptions& o, const VerifyResult& r);

/// One kernel x integrator (x transfer) series of a convergence study.
struct StudySeries {
  KernelKind kernel;
  std::string integrator;  ///< an explicit integrator or "implicit"
  Transfer transfer;
};
/// "linear:musl,cpgimp:cd:apic" (--series): kernel:integrator pairs with an optional transfer (default
/// `transfer`).
std::vector<StudySeries> parse_series(const std::string& text, Transfer transfer);

/// Run every series at every value of cells (vary_cells) or CFL, after validating every point; the rows of
/// study_row, each past a series' first with "order": log(e_prev / e) / log(h_prev / h), h ~ 1/cells or dt ~
/// cfl. Throws InputError (naming --values) for cells that are not whole numbers.
nlohmann::json convergence_rows(VerifyCase which, const VerifyOptions& base,
                                const std::vector<StudySeries>& series, bool vary_cells,
                                const std::vector<double>& values);

}  // namespace mpm

// `mpm verify CASE` and `mpm converge CASE`: manufactured solutions, their error norms and observed orders.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "mpm/verification/report.hpp"
#include "python_tool.hpp"

namespace mpm::app {

namespace {
/// Options shared by verify and converge.
struct CaseOptions {
  StudyRequest request;
  VerifyOptions& options = request.options;
  int threads = 0;
  bool json = false;

  void add_to(CLI::App* cmd) {
    cmd->add_option("case", request.case_name, "axis-aligned, bar-1d, expanding-ring or shear-wave")
        ->required();
    cmd->add_option("--dim", options.dim, "dimension (axis-aligned: 2 or 3)");
    cmd->add_option("--kernel", request.kernel, kernel_name_list());
    cmd->add_option("--transfer", request.transfer, "particle velocity update: flip or apic");
    cmd->add_option("--integrator", request.integrator, "usf, usl, cd, musl or implicit");
    cmd->add_option("--theta", options.theta, "implicit blend in [0, 1] (1: backward Euler, 0.5: midpoint)");
    cmd->add_option("--cells", options.cells, "cells per axis across the body");
    cmd->add_option("--ppc", options.ppc, "particles per cell per axis");
    cmd->add_option("--cfl", options.cfl, "CFL number in (0, 1], or (0, 2] with --cfl-speed reference");
    cmd->add_option("--cfl-speed", request.cfl_speed,
                    "wave speed of the CFL number: particles (max c_p + |v_p| every step) or reference "
                    "(c = sqrt(E / rho0), a fixed step)");
    cmd->add_option("--error", request.error,
                    "measure the displacement at the particles or the acceleration at the nodes (nodal)");
    cmd->add_option("--start", request.start,
                    "cd and musl start: halve the first acceleration, or from the exact v^(-1/2)");
    cmd->add_option(
        "--constrained-acceleration", request.constrained_acceleration,
        "acceleration on the symmetry planes' nodes: zero or velocity-difference (Steffen et al. 2008, "
        "Eq. 30)");
    cmd->add_option("--amplitude", options.amplitude, "displacement amplitude A");
    cmd->add_option("--nu", options.poisson,
                    "Poisson's ratio of the axis-aligned and shear-wave cases in [0, 0.5) (default 0.3)");
    cmd->add_option("--end-time", options.end_time, "end time (default: one period)");
    cmd->add_option("--threads", threads, "threads (0: all cores)")->check(CLI::Range(0, max_threads));
    cmd->add_flag("--json", json, "print JSON");
  }
  /// Parse names and validate; throws InputError naming the argument.
  VerifyCase resolve() {
    const VerifyCase c = request.resolve();
    set_num_threads(threads);
    return c;
  }
};

void write_csv(const std::filesystem::path& file, const ParticleTable& tab) {
  std::ofstream os(file);
  if (!os) throw InputError("--out: cannot write " + file.string());
  os.precision(17);
  for (std::size_t k = 0; k < tab.columns.size(); ++k) os << (k ? "," : "") << tab.columns[k];
  os << '\n';
  for (const std::vector<Real>& row : tab.rows) {
    for (std::size_t k = 0; k < row.size(); ++k) os << (k ? "," : "") << row[k];
    os << '\n';
  }
}

std::vector<double> parse_values(const std::string& text) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) throw InputError("--values: '" + item + "' is not a number");
    values.push_back(v);
  }
  if (values.size() < 2) throw InputError("--values: expected at least two comma-separated values");
  return values;
}
}  // namespace

Action add_verify(CLI::App& app) {
  auto c = std::make_shared<CaseOptions>();
  auto out = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("verify", "run a manufactured solution and report its error");
  c->add_to(cmd);
  cmd->add_option("--out", *out, "directory for the final particle states (particles.csv)");
  return [c, out]() {
    const VerifyCase which = c->resolve();
    ParticleTable final_state;
    const VerifyResult r = verify(which, c->options, out->empty() ? nullptr : &final_state);
    std::filesystem::path csv;
    if (!out->empty()) {
      std::filesystem::create_directories(*out);
      csv = std::filesystem::path(*out) / "particles.csv";
      write_csv(csv, final_state);
    }
    nlohmann::json j = study_row(which, c->options, r);
    if (!csv.empty()) j["particles_csv"] = csv.string();
    if (c->json) {
      std::cout << j.dump() << '\n';
    } else {
      std::cout << to_string(which) << ", " << c->request.kernel << " + " << c->request.integrator << ", "
                << c->options.cells << " cells per axis, " << r.steps << " steps to t = " << r.end_time
                << " s: " << (r.ok ? "ok" : "FAILED: " + r.failure) << "\n  L_inf = " << r.error.linf
                << "  L1 = " << r.error.l1() << "  L2 = " << r.error.l2() << '\n';
      if (!csv.empty()) std::cout << "  final particle states: " << csv.string() << '\n';
    }
    return r.ok ? 0 : exit_simulation_failure;
  };
}

namespace {
void write_table_csv(const std::string& file, const nlohmann::json& rows, const std::string& vary) {
  std::ofstream os(file);
  if (!os) throw InputError("--csv: cannot write " + file);
  os.precision(10);
  os << "kernel,integrator,transfer," << vary << ",linf,l1,l2,order,status,steps\n";
  for (const nlohmann::json& row : rows)
    os << row["kernel"].get<std::string>() << ',' << row["integrator"].get<std::string>() << ','
       << row["transfer"].get<std::string>() << ',' << row[vary] << ',' << row["linf"] << ',' << row["l1"]
       << ',' << row["l2"] << ',' << (row.contains("order") ? row["order"].dump() : "") << ','
       << row["status"].get<std::string>() << ',' << row["steps"] << '\n';
}

void print_table(const nlohmann::json& rows, const std::string& vary) {
  std::string current;
  for (const nlohmann::json& row : rows) {
    const std::string series = row["kernel"].get<std::string>() + " + " +
                               row["integrator"].get<std::string>() +
                               (row["transfer"] == "apic" ? " + apic" : "");
    if (series != current) {
      current = series;
      std::cout << row["case"].get<std::string>() << ", " << series << ", varying " << vary << "\n"
                << std::setw(10) << vary << std::setw(14) << "L_inf" << std::setw(14) << "L1" << std::setw(14)
                << "L2" << std::setw(9) << "order"
                << "  status\n";
    }
    std::cout << std::setw(10) << row[vary].get<double>() << std::setw(14) << row["linf"].get<double>()
              << std::setw(14) << row["l1"].get<double>() << std::setw(14) << row["l2"].get<double>()
              << std::setw(9);
    if (row.contains("order"))
      std::cout << std::fixed << std::setprecision(2) << row["order"].get<double>() << std::defaultfloat
                << std::setprecision(6);
    else
      std::cout << "";
    std::cout << "  " << row["status"].get<std::string>() << '\n';
  }
}

/// The log-log plot of every series, drawn by the embedded python/convergence.py.
void plot(const std::string& png, const nlohmann::json& rows, const std::string& vary,
          const std::string& title) {
  const std::filesystem::path data = std::filesystem::path(png).replace_extension(".plot.json");
  {
    std::ofstream os(data);
    if (!os) throw InputError("--plot: cannot write next to " + png);
    os << rows.dump();
  }
  nlohmann::json labels;  // each kernel's label, from the registry (shape/kernel_kind.hpp)
  for (const KernelEntry& e : kernel_registry) labels[std::string(e.name)] = std::string(e.label);
  run_python("convergence", {data.string(), png, vary, title, labels.dump()}, "--plot");
  std::filesystem::remove(data);
}
}  // namespace

Action add_converge(CLI::App& app) {
  auto c = std::make_shared<CaseOptions>();
  auto vary = std::make_shared<std::string>();
  auto values = std::make_shared<std::string>();
  auto series_text = std::make_shared<std::string>();
  auto csv = std::make_shared<std::string>();
  auto png = std::make_shared<std::string>();
  auto title = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("converge", "error table and observed orders over cells or CFL");
  c->add_to(cmd);
  cmd->add_option("--vary", *vary, "cells or cfl")->required();
  cmd->add_option("--values", *values, "comma-separated values, e.g. 8,16,32")->required();
  cmd->add_option("--series", *series_text,
                  "several kernel:integrator[:transfer] series in one study, e.g. "
                  "cpgimp:cd,linear:musl,bspline2:usl:apic "
                  "(replaces --kernel and --integrator)");
  cmd->add_option("--csv", *csv, "write the table to this CSV file");
  cmd->add_option("--plot", *png,
                  "write a log-log plot of every series to this PNG file (needs python3-matplotlib)");
  cmd->add_option("--title", *title, "title of the plot (default: the case and what varies)");
  return [c, vary, values, series_text, csv, png, title]() {
    if (*vary != "cells" && *vary != "cfl")
      throw InputError("--vary: expected cells or cfl, got '" + *vary + "'");
    const bool vary_cells = *vary == "cells";
    const std::vector<double> vals = parse_values(*values);
    const VerifyCase which = c->resolve();
    const std::vector<StudySeries> series =
        series_text->empty()
            ? std::vector<StudySeries>{{c->options.kernel, c->request.integrator, c->options.transfer}}
            : parse_series(*series_text, c->options.transfer);
    const nlohmann::json rows = convergence_rows(which, c->options, series, vary_cells, vals);
    if (!csv->empty()) write_table_csv(*csv, rows, *vary);
    if (!png->empty())
      plot(*png, rows, *vary,
           !title->empty() ? *title
                           : std::string(to_string(which)) +
                                 (vary_cells ? ": spatial convergence" : ": temporal convergence"));
    if (c->json)
      std::cout << rows.dump() << '\n';
    else
      print_table(rows, *vary);
    return 0;
  };
}

}  // namespace mpm::app

// `mpm verify CASE`: run a manufactured solution and report its error norms.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/verification/axis_aligned.hpp"
#include "mpm/verification/study.hpp"

namespace mpm::app {

namespace {
struct VerifyCommand {
  std::string case_name;
  std::string kernel = "cpgimp";
  std::string integrator = "cd";
  VerifyOptions options;
  std::string out;
  int threads = 0;
  bool json = false;
};

/// Write final particle states (reference and current position, velocity, J, stress, error) as CSV.
void write_particles(const std::filesystem::path& file, const ParticleSet<2>& p, const AxisAligned& exact,
                     Real t) {
  std::ofstream os(file);
  if (!os) throw InputError("--out: cannot write " + file.string());
  os.precision(17);
  os << "X,Y,x,y,vx,vy,J,sigma_xx,sigma_yy,sigma_xy,error\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Real err = ((p.x[i] - p.X[i]) - exact.displacement(p.X[i], t)).norm();
    os << p.X[i][0] << ',' << p.X[i][1] << ',' << p.x[i][0] << ',' << p.x[i][1] << ',' << p.v[i][0] << ','
       << p.v[i][1] << ',' << p.F[i].determinant() << ',' << p.sigma[i](0, 0) << ',' << p.sigma[i](1, 1) << ','
       << p.sigma[i](0, 1) << ',' << err << '\n';
  }
}
}  // namespace

Action add_verify(CLI::App& app) {
  auto c = std::make_shared<VerifyCommand>();
  CLI::App* cmd = app.add_subcommand("verify", "run a manufactured solution and report its error");
  cmd->add_option("case", c->case_name, "axis-aligned")->required();
  cmd->add_option("--kernel", c->kernel, "linear, ugimp, cpgimp, bspline2 or bspline3");
  cmd->add_option("--integrator", c->integrator, "usf, usl, cd or musl");
  cmd->add_option("--cells", c->options.cells, "cells per axis across the body");
  cmd->add_option("--ppc", c->options.ppc, "particles per cell per axis");
  cmd->add_option("--cfl", c->options.cfl, "CFL number in (0, 1]");
  cmd->add_option("--amplitude", c->options.amplitude, "displacement amplitude A");
  cmd->add_option("--end-time", c->options.end_time, "end time (default: one period)");
  cmd->add_option("--out", c->out, "directory for the final particle states (particles.csv)");
  cmd->add_option("--threads", c->threads, "threads (0: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--json", c->json, "print one JSON object");
  return [c]() {
    if (c->case_name != "axis-aligned")
      throw InputError("case: unknown case '" + c->case_name + "' (expected axis-aligned)");
    c->options.kernel = parse_kernel(c->kernel, "--kernel");
    c->options.integrator = parse_integrator(c->integrator, "--integrator");
    validate(c->options);
    set_num_threads(c->threads);
    const AxisAligned exact{c->options.amplitude, NeoHookean::from_young_poisson(1e7, 0.3, 1000)};
    std::filesystem::path csv;
    if (!c->out.empty()) {
      std::filesystem::create_directories(c->out);
      csv = std::filesystem::path(c->out) / "particles.csv";
    }
    Real t_end = 0;
    const VerifyResult r = verify_axis_aligned(c->options, [&](const ParticleSet<2>& p) {
      if (!csv.empty()) write_particles(csv, p, exact, t_end);
    });
    t_end = r.end_time;
    nlohmann::json j{{"case", c->case_name},       {"dim", 2},
                     {"kernel", c->kernel},        {"integrator", c->integrator},
                     {"cells", c->options.cells},  {"ppc", c->options.ppc},
                     {"cfl", c->options.cfl},      {"amplitude", c->options.amplitude},
                     {"end_time", r.end_time},     {"steps", r.steps},
                     {"linf", r.error.linf},       {"l1", r.error.l1()},
                     {"l2", r.error.l2()},         {"status", r.ok ? "ok" : "failed"}};
    if (!r.ok) j["failure"] = r.failure;
    if (!csv.empty()) j["particles_csv"] = csv.string();
    if (c->json) {
      std::cout << j.dump() << '\n';
    } else {
      std::cout << "axis-aligned, " << c->kernel << " + " << c->integrator << ", " << c->options.cells << "x"
                << c->options.cells << " cells, " << r.steps << " steps to t = " << r.end_time << " s: "
                << (r.ok ? "ok" : "FAILED: " + r.failure) << "\n  L_inf = " << r.error.linf
                << "  L1 = " << r.error.l1() << "  L2 = " << r.error.l2() << '\n';
      if (!csv.empty()) std::cout << "  final particle states: " << csv.string() << '\n';
    }
    return r.ok ? 0 : exit_simulation_failure;
  };
}

}  // namespace mpm::app

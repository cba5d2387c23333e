// `mpm bench`: the reference elastic block, timed.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "commands.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/generate.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "roofline.hpp"

namespace mpm::app {

namespace {
/// The most memory the process has held (its peak resident set, Linux's VmHWM, which starts afresh at exec
/// where getrusage's maximum carries over the parent's), all ranks' together.
double peak_resident_bytes() {
  std::int64_t kib = 0;
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) kib = std::stoll(line.substr(6));
  if (kib == 0) {  // no /proc: the resource usage's maximum
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    kib = usage.ru_maxrss;
  }
  std::vector<std::int64_t> bytes{1024 * kib};
  world().sum(bytes);
  return static_cast<double>(bytes[0]);
}

struct BenchOptions {
  int dim = 2;
  std::string kernel = "linear";
  std::string integrator = "usl";
  std::string transfer = "flip";
  long particles = 102400;
  int steps = 200;
  int threads = 0;
  int repeat = 3;
  bool json = false;
  bool contact = false;
  bool roofline = false;
  std::string material = "neo-hookean";
};

/// The bench block's material: the Neo-Hookean solid (E = 1 MPa, nu = 0.3, rho = 1000 kg/m^3), the
/// hypoelastic one of the same moduli (the rate-form path without a return), or a frictional one of the same
/// elasticity weak enough to yield under the block's weight (c = 1 kPa, phi = 30 degrees, psi = 0; the weight
/// gives 9.8 kPa at the base), so that the plastic returns are timed.
Material bench_material(const std::string& name) {
  if (name == "neo-hookean") return NeoHookean::from_young_poisson(1e6, 0.3, 1000);
  if (name == "hypoelastic") {
    ElastoPlastic law;
    law.E = 1e6;
    law.nu = 0.3;
    law.rho0 = 1000;
    return law;
  }
  FrictionalSolid solid;
  solid.E = 1e6;
  solid.nu = 0.3;
  solid.rho0 = 1000;
  solid.strength.cohesion = solid.strength.residual_cohesion = 1e3;
  solid.strength.friction = solid.strength.residual_friction = std::numbers::pi / 6;
  if (name == "drucker-prager") return DruckerPrager{solid};
  return MohrCoulomb{solid};
}

/// The reference problem: a 1 m elastic block (E = 1 MPa, nu = 0.3, rho = 1000 kg/m^3) under gravity on
/// fixed nodes (all nodes at or below the block's base), 2 particles per cell per axis, 0.05 m of grid around
/// it, dt = 5e-5 s on cells of 1/160 m or wider and in proportion to h on finer ones (the Courant number of
/// the reference size, c dt / h = 0.29 with the P-wave speed c = 36.7 m/s). particle_steps_per_second is the
/// whole run's: all ranks' particles over the slowest rank's time. With `contact` the block's two halves (x <
/// 1/2 and x >= 1/2) have a velocity field each and meet by frictionless contact all along their interface.
template <int Dim, class Kernel>
nlohmann::json run_block(const BenchOptions& o, KernelKind kind, Integrator integrator) {
  const int ppc = 2;
  const int n = std::max(1, static_cast<int>(std::lround(
                                std::pow(static_cast<double>(o.particles) / std::pow(ppc, Dim), 1.0 / Dim))));
  const Real h = 1.0 / n;
  const int pad = static_cast<int>(std::ceil(0.05 / h - 1e-9));
  SimulationSpec<Dim> spec;
  spec.h = h;
  spec.grid_lo = Vec<Dim>::Constant(-pad * h);
  spec.cells.fill(n + 2 * pad);
  spec.kernel = kind;
  spec.transfer = o.transfer == "apic" ? Transfer::apic : Transfer::flip;
  spec.integrator = integrator;
  spec.materials = {bench_material(o.material)};
  spec.gravity = Vec<Dim>::Zero();
  spec.gravity[Dim - 1] = -9.81;
  spec.dt = 5e-5 * std::min(1.0, 160 * h);
  RegionConstraint<Dim> floor{Vec<Dim>::Constant(-1e30), Vec<Dim>::Constant(1e30), {}};
  floor.hi[Dim - 1] = 0;
  spec.boundary.regions.push_back(floor);
  if (o.contact) spec.contact = ContactSpec{2, {ContactPair{0, 1, 0.0}}};
  // Seeded afresh for each run and moved into it, so that the process holds one copy, as `mpm run` does.
  const auto seed = [&] {
    ParticleSet<Dim> particles;
    fill_box<Dim>(particles, Vec<Dim>::Zero(), Vec<Dim>::Ones(), h / ppc, 1000, 0);
    if (o.contact)
      for (std::size_t i = 0; i < particles.size(); ++i) particles.field[i] = particles.x[i][0] < 0.5 ? 0 : 1;
    return particles;
  };

  // Under mpirun the ranks divide the block (Simulation with world()): a run's time is the slowest rank's,
  // from a common start, and its time in communication the largest of the ranks' (waiting for the others
  // included).
  const Communicator& comm = world();
  std::vector<double> seconds, communication;
  std::int64_t sent = 0;
  double bytes = 0;
  std::size_t count = 0;  // every rank seeds the whole block and keeps its own part
  for (int r = 0; r < o.repeat; ++r) {
    // Counted from the set the run is given: a set seeded only to be counted and freed would leave glibc's
    // heap holding its pages (a freed array below 32 MiB raises the size malloc takes from the heap, not from
    // mmap).
    ParticleSet<Dim> seeded = seed();
    count = seeded.size();
    Simulation<Dim, Kernel> sim(spec, std::move(seeded), comm);
    comm.min(0);
    const double c0 = comm.seconds();
    const std::int64_t b0 = comm.bytes_sent();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < o.steps; ++s) sim.step();
    const double mine = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double talk = comm.seconds() - c0;
    seconds.push_back(comm.max(mine));
    communication.push_back(comm.max(talk));
    sent = static_cast<std::int64_t>(comm.max(static_cast<double>(comm.bytes_sent() - b0)));
    bytes = sim.bytes_per_particle();
  }
  std::vector<std::size_t> runs(seconds.size());
  for (std::size_t k = 0; k < runs.size(); ++k) runs[k] = k;
  std::sort(runs.begin(), runs.end(), [&](std::size_t a, std::size_t b) { return seconds[a] < seconds[b]; });
  const std::size_t mid = runs[runs.size() / 2];
  const double median = seconds[mid];
  return {{"dim", Dim},
          {"kernel", to_string(kind)},
          {"integrator", to_string(integrator)},
          {"transfer", o.transfer},
          {"ranks", comm.size()},
          {"fields", spec.contact.fields},
          {"material", o.material},
          {"threads", num_threads()},
          {"communication_seconds", communication[mid]},
          {"bytes_sent_per_step", static_cast<double>(sent) / o.steps},  // the most any rank sent
          {"particles", count},
          {"cells_per_axis", n + 2 * pad},
          {"steps", o.steps},
          {"seconds", median},
          {"seconds_all_runs", seconds},
          {"particle_steps_per_second", static_cast<double>(count) * o.steps / median},
          {"bytes_per_particle", bytes},
          {"peak_resident_bytes", peak_resident_bytes()}};
}
int print_roofline(bool json) {
  const Roofline r = measure_roofline();
  if (json) {
    std::cout << nlohmann::json{{"threads", r.threads},
                                {"triad_bytes_per_second", r.triad_bytes_per_second},
                                {"fused_flops_per_second", r.fused_flops_per_second},
                                {"separate_flops_per_second", r.separate_flops_per_second}}
                     .dump()
              << '\n';
  } else {
    std::cout << r.threads << " threads: memory " << r.triad_bytes_per_second / 1e9
              << " GB/s (STREAM triad), " << r.fused_flops_per_second / 1e9
              << " GFLOP/s with fused multiply-adds, " << r.separate_flops_per_second / 1e9
              << " GFLOP/s with separate multiplies and adds\n";
  }
  return 0;
}
}  // namespace

Action add_bench(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "time the reference elastic block problem");
  cmd->add_option("--dim", o->dim, "dimension: 2 or 3")->check(CLI::IsMember({2, 3}));
  cmd->add_option("--kernel", o->kernel, kernel_name_list());
  cmd->add_option("--integrator", o->integrator, "usf, usl, cd or musl");
  cmd->add_option("--transfer", o->transfer, "particle velocity update: flip or apic")
      ->check(CLI::IsMember({"flip", "apic"}));
  cmd->add_option("--particles", o->particles, "approximate particle count")
      ->check(CLI::Range(1L, 1000000000L));
  cmd->add_option("--steps", o->steps, "time steps per run")->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o->threads, "threads (0: all cores)")->check(CLI::Range(0, max_threads));
  cmd->add_option("--repeat", o->repeat, "runs; the median is reported")->check(CLI::PositiveNumber);
  cmd->add_flag("--json", o->json, "print one JSON object");
  cmd->add_flag(
      "--roofline", o->roofline,
      "measure the machine's memory bandwidth (STREAM triad) and arithmetic peak instead of the block");
  cmd->add_flag("--contact", o->contact, "split the block into two halves meeting by frictionless contact");
  cmd->add_option("--material", o->material, "neo-hookean, hypoelastic, drucker-prager or mohr-coulomb")
      ->check(CLI::IsMember({"neo-hookean", "hypoelastic", "drucker-prager", "mohr-coulomb"}));
  return [o]() {
    const KernelKind kind = parse_kernel(o->kernel, "--kernel");
    const Integrator integrator = parse_integrator(o->integrator, "--integrator");
    set_num_threads(o->threads);
    if (o->roofline) return print_roofline(o->json);
    auto run = [&]<int Dim>() {
      return with_kernel<Dim>(kind, [&]<class K>() { return run_block<Dim, K>(*o, kind, integrator); });
    };
    const nlohmann::json result = o->dim == 2 ? run.operator()<2>() : run.operator()<3>();
    if (world().rank() != 0) return 0;
    if (o->json) {
      std::cout << result.dump() << '\n';
    } else {
      std::cout << result["dim"] << "-D " << o->kernel << " " << o->integrator
                << (o->contact ? " contact" : "") << (o->transfer == "apic" ? " apic" : "") << " "
                << o->material << ", " << result["particles"] << " particles, " << result["ranks"]
                << " ranks x " << result["threads"] << " threads: " << result["seconds"].get<double>()
                << " s median of " << o->repeat << ", "
                << result["particle_steps_per_second"].get<double>() / 1e6 << " M particle-steps/s, "
                << result["bytes_per_particle"].get<double>() << " B/particle, "
                << result["communication_seconds"].get<double>() << " s communicating\n";
    }
    return 0;
  };
}

}  // namespace mpm::app

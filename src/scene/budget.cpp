#include "mpm/scene/budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "mpm/core/errors.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/io/hdf5_columns.hpp"
#include "mpm/particles/stable_step.hpp"

namespace mpm {

namespace {
namespace fs = std::filesystem;

/// Lattice points per axis of fill_box over [lo, hi] (the same floor as fill_box).
double lattice(double lo, double hi, double spacing) {
  return std::floor((hi - lo) / spacing + 1e-9);
}

/// Bounding boxes with at most this many lattice points are counted point by point.
constexpr double exact_count_limit = 4e6;

double count_box(const Scene& sc, const SceneShape& b) {
  double n = 1;
  for (int d = 0; d < sc.dim; ++d) n *= lattice(b.lo[d], b.hi[d], sc.h / b.ppc);
  return n;
}

/// Disk, sphere or ring: the lattice points of the bounding box inside the shape.
double count_round(const Scene& sc, const SceneShape& b) {
  const double s = sc.h / b.ppc, r = b.radius, r_in = b.inner_radius;
  const double per_axis = lattice(-r, r, s);
  const double box = std::pow(per_axis, sc.dim);
  if (box > exact_count_limit) {  // the shape's share of its bounding box
    const double ball = sc.dim == 2 ? M_PI / 4 : M_PI / 6;
    return box * ball * (1 - std::pow(r_in / r, sc.dim));
  }
  const auto n = static_cast<long>(per_axis);
  double count = 0;
  auto at = [&](long k) { return -r + (static_cast<double>(k) + 0.5) * s; };  // offsets from the centre
  for (long i = 0; i < n; ++i)
    for (long j = 0; j < n; ++j)
      for (long k = 0; k < (sc.dim == 3 ? n : 1); ++k) {
        const double rr = std::sqrt(at(i) * at(i) + at(j) * at(j) + (sc.dim == 3 ? at(k) * at(k) : 0.0));
        count += rr <= r && rr >= r_in;
      }
  return count;
}

/// Data rows of a particle file: an HDF5 file's values per dataset, or a CSV file's lines that are neither
/// empty, comments, nor a header on line 1.
double count_file(const SceneShape& b) {
  if (io::is_hdf5_file(b.file)) return static_cast<double>(io::read_hdf5_columns(b.file).values[0].size());
  std::ifstream is(b.file);
  double rows = 0;
  bool first = true;
  for (std::string line; std::getline(is, line); first = false) {
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    if (first && std::isalpha(static_cast<unsigned char>(line[start]))) continue;
    ++rows;
  }
  return rows;
}

/// A polygon's particles, at most: its area over a particle's, plus a particle for each spacing of its
/// perimeter (the lattice points near its edges).
double count_polygon(const Scene& sc, const SceneShape& b) {
  const double s = sc.h / b.ppc;
  const std::vector<Vec<2>>& v = b.polygon.vertices;
  double perimeter = 0;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) perimeter += (v[i] - v[j]).norm();
  return std::abs(b.polygon.signed_area()) / (s * s) + perimeter / s + 1;
}

double count_shape(const Scene& sc, const SceneShape& b) {
  switch (b.shape) {
    case SceneBody::Shape::box:
      return count_box(sc, b);
    case SceneBody::Shape::file:
      return count_file(b);
    case SceneBody::Shape::polygon:
      return count_polygon(sc, b);
    case SceneBody::Shape::surface: {  // its volume over a particle's, plus a layer of them over its area
      const double s = sc.h / b.ppc;
      return b.surface.volume() / (s * s * s) + b.surface.area() / (s * s) + 1;
    }
    case SceneBody::Shape::mesh:  // its Gauss points, which only the body holds: count_body
      return 0;
    case SceneBody::Shape::disk:
    case SceneBody::Shape::ring:
      break;
  }
  return count_round(sc, b);
}

/// A body's particles, at most: its shape's and those of the shapes it adds (what it subtracts or intersects
/// with is not counted off).
double count_body(const Scene& sc, const SceneBody& b) {
  double n = count_shape(sc, b) + static_cast<double>(b.mesh_points.size());
  for (const SceneShape& s : b.add) n += count_shape(sc, s);
  return n;
}

/// The largest wave speed at rest of the scene's materials [m/s].
double wave_speed_at_rest(const Scene& sc) {
  double c = 0;
  for (const SceneMaterial& m : sc.materials) c = std::max(c, mpm::wave_speed_at_rest(m.law));
  return c;
}

/// The first step [s]: the scene's dt, or the CFL condition on the fastest wave at rest plus the fastest
/// particle's speed `speed`, times the implicit engine's step factor.
double first_dt(const Scene& sc, double speed) {
  const double explicit_dt = sc.dt > 0 ? sc.dt : cfl_step(sc.cfl, sc.h, wave_speed_at_rest(sc) + speed);
  return sc.implicit ? explicit_dt * sc.implicit_step.step_factor : explicit_dt;
}

template <int Dim>
MemoryModel engine_memory(const Scene& sc) {
  return with_kernel<Dim>(sc.kernel, [&]<class Kernel>() {
    if (sc.implicit)
      return ImplicitSimulation<Dim, Kernel>::memory_model(
          sc.implicit_step.newton.restart,
          sc.implicit_step.frozen_jacobian || sc.implicit_step.solver == ImplicitSolver::newton_direct);
    bool rate_form = false;
    for (const SceneMaterial& m : sc.materials) rate_form = rate_form || is_rate_form(m.law);
    int grids = sc.fields;  // one per velocity field, and one more each for the gaps of [[contact]]
    for (const SceneContact& c : sc.contacts)
      if (std::isfinite(c.gap)) grids = 2 * sc.fields;
    const bool located_half_lengths =  // USF keeps cpGIMP's (Simulation::keep_located_half_lengths)
        sc.integrator == Integrator::usf && half_lengths_of(sc.kernel) == HalfLengths::deformed;
    return Simulation<Dim, Kernel>::memory_model(!sc.body_force.empty(), rate_form, located_half_lengths,
                                                 grids, !sc.surface_loads.empty());
  });
}

MemoryModel engine_memory(const Scene& sc) {
  return sc.dim == 1 ? engine_memory<1>(sc) : sc.dim == 2 ? engine_memory<2>(sc) : engine_memory<3>(sc);
}

/// Whether the particles carry a material state: in implicit runs, and in explicit runs with a rate-form
/// material.
bool has_material_state(const Scene& sc) {
  return sc.implicit || std::any_of(sc.materials.begin(), sc.materials.end(),
                                    [](const SceneMaterial& m) { return is_rate_form(m.law); });
}

/// Bytes per particle of one particles_NNNN.vtp: the fields scene_run writes (velocity, displacement, stress,
/// F, J, volume, mass, material, id; error with [check]; with a material state, plastic strain, temperature
/// rise, internal energy and the internal variables the laws declare), the points, and two 8-byte integers of
/// vertex cells.
double frame_bytes_per_particle(const Scene& sc) {
  const std::size_t state = has_material_state(sc) ? 3 + declared_columns(material_laws(sc)).size() : 0;
  const std::size_t components = 3 + 3 + 6 + 9 + 5 + (sc.exact_displacement.empty() ? 0 : 1) + state;
  return 8.0 * static_cast<double>(components + 3 + 2);
}

/// Bytes per particle of checkpoint.h5: the particle arrays (x, X, v, F, m, V0, material, field, id; l0 for
/// the kernels that keep it) and with a material state, its arrays (stress, plastic strain, temperature,
/// energy, stretch, volume, the laws' internal variables).
double checkpoint_bytes_per_particle(const Scene& sc) {
  const bool half_lengths =
      with_kernel<2>(sc.kernel, []<class Kernel>() { return reads_half_lengths<Kernel>; });
  const std::size_t values = static_cast<std::size_t>((half_lengths ? 4 : 3) * sc.dim + sc.dim * sc.dim + 4) +
                             (has_material_state(sc) ? 11 + internal_columns : 0);
  return 8.0 * static_cast<double>(values);
}

std::string bytes_text(double bytes) {
  static constexpr const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) bytes /= 1000, ++u;
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.3g %s", bytes, units[u]);
  return buffer;
}

std::string seconds_text(double t) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g s", t);
  return buffer;
}

std::string count_text(double n) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, n < 1e7 ? "%.0f" : "%.3g", n);
  return buffer;
}

[[noreturn]] void refuse(const Scene& sc, const std::string& where, const std::string& what) {
  throw InputError(sc.file.string() + ": " + where + ": " + what);
}
}  // namespace

Budget estimate_budget(const Scene& sc, double initial_speed, double start_time) {
  Budget b;
  for (std::size_t k = 0; k < sc.bodies.size(); ++k) {
    const double n = count_body(sc, sc.bodies[k]);
    b.bodies.push_back({"bodies[" + std::to_string(k) + "] (" + sc.bodies[k].name + ")", n});
    b.particles += n;
  }
  const int ghost =
      with_kernel<3>(sc.kernel, []<class Kernel>() { return Kernel::ghost; });  // the same in every Dim
  b.nodes = 1;
  for (int d = 0; d < sc.dim; ++d) b.nodes *= sc.cells[d] + 1.0 + 2.0 * ghost;

  // From start_time (a restart's) to the end: the steps, and the frames the run adds (t = 0's, k every, the
  // last).
  const double span = sc.end_time - start_time;
  b.first_dt = first_dt(sc, initial_speed);
  b.steps = std::max(1.0, std::ceil(span / b.first_dt * (1 - 1e-14)));
  b.frames = (start_time > 0 ? 1 : 2) + (sc.output_every > 0 ? std::floor(sc.end_time / sc.output_every) -
                                                                   std::floor(start_time / sc.output_every)
                                                             : 0);

  // Memory: the engine's arrays, the velocities of the step before for the work of the loads (the implicit
  // runner's copy; the explicit engine's, with their tiles, when there are loads), and the largest transient
  // output: a frame (its fields, the file's bytes and their assembly) or a checkpoint.
  const double frame = frame_bytes_per_particle(sc), checkpoint = checkpoint_bytes_per_particle(sc);
  const bool loads = !sc.body_force.empty() || !sc.surface_loads.empty() ||
                     std::any_of(sc.gravity.begin(), sc.gravity.end(), [](double g) { return g != 0; });
  const double before = sc.implicit ? sc.dim * 8.0 : loads ? sc.dim * 8.0 + 4 : 0;
  const double runner = before + std::max(3 * frame, 2 * checkpoint);
  const MemoryModel engine = engine_memory(sc);
  constexpr double process = 16e6;  // the program, its libraries and thread stacks (measured: 14-15 MB)
  b.memory_bytes = process + engine.bytes(b.particles, b.nodes) + runner * b.particles;

  // Output: frames, one history row per step (about 24 characters per column), one checkpoint plus its
  // temporary copy during the atomic replace, and the small files (summary, series, their headers).
  const double columns = 6 + sc.dim * (1 + 2 * sc.dim + static_cast<double>(sc.rigid_bodies.size()));
  b.output_bytes = b.frames * (b.particles * frame + 4096) + (b.steps + 1) * 24 * columns +
                   2 * (b.particles * checkpoint + 65536) + 65536;
  // newton.csv: about four rows of five columns a step (the examples' steps take 1 to 10 Newton iterations).
  if (sc.newton_log) b.output_bytes += b.steps * 4 * 24 * 5;
  return b;
}

void check_initial_speed(const Scene& sc, const std::string& where, double speed) {
  if (!std::isfinite(speed)) refuse(sc, where, "a particle's initial speed overflows (|v| is not finite)");
  const double dt = first_dt(sc, speed), steps = sc.end_time / dt;
  if (steps > limits::max_steps)
    refuse(sc, where,
           "a particle starts at " + count_text(speed) + " m/s: about " + count_text(steps) + " steps of " +
               seconds_text(dt) + "; a run takes at most " + count_text(limits::max_steps) + " steps");
}

void check_budget(const Scene& sc, const Budget& b, const BudgetLimits& lim) {
  const auto largest = std::max_element(
      b.bodies.begin(), b.bodies.end(),
      [](const BodyEstimate& x, const BodyEstimate& y) { return x.particles < y.particles; });
  if (b.particles > limits::max_particles)
    refuse(sc, largest->name,
           "seeds about " + count_text(largest->particles) + " particles (" + count_text(b.particles) +
               " in all); a run holds at most 2^31 - 1 (2147483647): use a smaller ppc or a coarser grid");
  if (b.nodes > limits::max_nodes)
    refuse(sc, "grid.cells", count_text(b.nodes) + " grid nodes; a run holds at most 2^31 - 1 (2147483647)");
  if (b.steps > limits::max_steps)
    refuse(sc, "simulation.end_time",
           "about " + count_text(b.steps) + " steps of " + seconds_text(b.first_dt) +
               "; a run takes at most " + count_text(limits::max_steps) +
               " steps (split a longer run with --stop-after and --restart)");
  if (b.memory_bytes > lim.max_memory_bytes)
    refuse(sc, largest->name,
           "the run needs about " + bytes_text(b.memory_bytes) + " of memory (" + count_text(b.particles) +
               " particles, " + count_text(largest->particles) + " in this body; " + count_text(b.nodes) +
               " nodes), more than the " + bytes_text(lim.max_memory_bytes) + " allowed (--max-memory)");
  if (b.output_bytes > lim.free_bytes)
    refuse(sc, "output",
           "the run writes about " + bytes_text(b.output_bytes) + " (" + count_text(b.frames) +
               " frames of " + count_text(b.particles) + " particles, " + count_text(b.steps) +
               " history rows), more than the " + bytes_text(lim.free_bytes) + " free under --out");
}

std::string describe(const Budget& b) {
  return "budget: " + count_text(b.particles) + " particles, " + count_text(b.nodes) + " nodes, " +
         bytes_text(b.memory_bytes) + " memory, " + count_text(b.steps) + " steps (dt " +
         seconds_text(b.first_dt) + "), " + count_text(b.frames) + " frames, " + bytes_text(b.output_bytes) +
         " output";
}

double physical_memory_bytes() {
  return static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

double free_space_bytes(const fs::path& path) {
  fs::path at = fs::absolute(path);
  std::error_code ec;
  while (!fs::exists(at, ec) && at.has_parent_path() && at != at.parent_path()) at = at.parent_path();
  const fs::space_info info = fs::space(at, ec);
  return ec ? 0.0 : static_cast<double>(info.available);
}

}  // namespace mpm

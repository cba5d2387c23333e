#pragma once
// The checkpoint of a scene run: the particle arrays, the clock, the engine's state and the run's
// accumulators, bit for bit, so that a restart ends bitwise equal to an uninterrupted run.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/scene/scene.hpp"
#include "mpm/verification/error_norms.hpp"
#include "run_arrays.hpp"
#include "scene_engine.hpp"

namespace mpm::scene_checkpoint {

/// What a run accumulates besides the particles.
struct Accumulators {
  std::int64_t frames = 0;        ///< particle outputs written
  Real last_frame_time = -1;      ///< time of the last one
  Real external_work = 0;         ///< work of the loads and moving constraints since t = 0 [J]
  Real friction_dissipation = 0;  ///< energy friction dissipated on the Coulomb walls since t = 0 [J]
  ErrorNorms error;               ///< the [check] error norms so far
};

/// What has left through outflow faces, into a checkpoint and back. A checkpoint written before outflow faces
/// existed holds none of it: nothing had left.
template <int Dim>
void save_outflow(const Outflow<Dim>& out, io::CheckpointData& c) {
  c.integer_scalars["outflow_particles"] = out.particles;
  c.real_scalars["outflow_mass"] = out.mass;
  c.real_scalars["outflow_kinetic_energy"] = out.kinetic_energy;
  c.real_scalars["outflow_internal_energy"] = out.internal_energy;
  c.reals["outflow_momentum"] = std::vector<double>(out.momentum.data(), out.momentum.data() + Dim);
}
template <int Dim>
Outflow<Dim> load_outflow(const io::CheckpointData& c, const std::string& where) {
  Outflow<Dim> out;
  const auto gone = c.integer_scalars.find("outflow_particles");
  if (gone == c.integer_scalars.end()) return out;
  out.particles = gone->second;
  out.mass = scene_engines::entry(c.real_scalars, "outflow_mass", where);
  out.kinetic_energy = scene_engines::entry(c.real_scalars, "outflow_kinetic_energy", where);
  // Checkpoints written before the history column's name changed hold it as outflow_strain_energy.
  out.internal_energy =
      scene_engines::entry(c.real_scalars,
                           c.real_scalars.contains("outflow_internal_energy") ? "outflow_internal_energy"
                                                                              : "outflow_strain_energy",
                           where);
  const std::vector<double>& momentum = scene_engines::entry(c.reals, "outflow_momentum", where);
  if (momentum.size() != Dim) throw InputError(where + ": array 'outflow_momentum' has the wrong size");
  std::copy(momentum.begin(), momentum.end(), out.momentum.data());
  return out;
}

template <int Dim>
io::CheckpointData save(const Scene& sc, const SceneEngine<Dim>& engine, const Accumulators& a) {
  using scene_engines::flat;
  const ParticleSet<Dim>& p = engine.particles();
  io::CheckpointData c;
  c.texts["scene"] = sc.text;
  c.integer_scalars = {{"dim", Dim},
                       {"particles", engine.particle_count()},
                       {"steps", engine.steps()},
                       {"frames", a.frames},
                       {"error_samples", a.error.samples}};
  c.real_scalars = {{"time", engine.time()},
                    {"external_work", a.external_work},
                    {"friction_dissipation", a.friction_dissipation},
                    {"last_frame_time", a.last_frame_time},
                    {"error_linf", a.error.linf},
                    {"error_sum", a.error.sum},
                    {"error_sum_sq", a.error.sum_sq}};
  c.reals = {{"x", flat(p.x)}, {"X", flat(p.X)}, {"v", flat(p.v)},
             {"F", flat(p.F)}, {"m", p.m},       {"V0", p.V0}};
  c.integers["material"] = std::vector<std::int64_t>(p.material.begin(), p.material.end());
  c.integers["field"] = std::vector<std::int64_t>(p.field.begin(), p.field.end());
  c.integers["id"] = p.id;
  // Divided between ranks, each rank's particles are its rows of these.
  c.row_widths = {{"x", Dim}, {"X", Dim},      {"v", Dim},   {"F", Dim * Dim}, {"m", 1},
                  {"V0", 1},  {"material", 1}, {"field", 1}, {"id", 1}};
  if (p.half_lengths !=
      HalfLengths::none) {  // GIMP's and CPDI's (every rank writes them, one with no particles too)
    c.reals["l0"] = flat(p.l0);
    c.row_widths["l0"] = Dim;
  }
  // The optional arrays go by the run's choices, not by whether this rank holds any particle: every rank of a
  // divided run writes the same arrays (HDF5 creates them together).
  if (engine.transfer() == Transfer::apic) {  // APIC's affine matrices
    c.reals["B"] = flat(p.B);
    c.row_widths["B"] = Dim * Dim;
  }
  if (engine.kernel() == KernelKind::cpdi2) {  // CPDI2's domain corners
    c.reals["corners"] = flat(p.corners);
    c.row_widths["corners"] = Dim << Dim;
  }
  save_outflow(engine.outflow(), c);
  engine.save(c);
  return c;
}

namespace detail {
template <class Map>
const auto& scalar(const Map& map, const std::string& key, const std::string& where) {
  auto it = map.find(key);
  if (it == map.end()) throw InputError(where + ": not a checkpoint of a scene run (no '" + key + "')");
  return it->second;
}

/// What restore() sets from this rank's share alone, with no other rank: its particles, the engine's state of
/// them and the accumulators.
template <int Dim>
void load_share(const io::CheckpointData& c, SceneEngine<Dim>& engine, Accumulators& a, std::int64_t seeded,
                const std::string& where) {
  using scene_engines::unflat;
  const auto other_scene = [&] {
    return InputError(where +
                      ": the checkpoint holds a different scene (dimension or particle count differ)");
  };
  if (scalar(c.integer_scalars, "dim", where) != Dim) throw other_scene();
  const std::int64_t particles = scalar(c.integer_scalars, "particles", where);
  const Outflow<Dim> out = load_outflow<Dim>(c, where);
  if (particles < 0 || out.particles < 0 || particles + out.particles != seeded) throw other_scene();
  engine.restore_outflow(out);
  // A checkpoint of an mpm older than divided runs marks no rows, and each rank would hold them all.
  if (c.row_widths.empty() && engine.communicator().size() > 1)
    throw InputError(where +
                     ": a checkpoint written before runs could be divided between ranks; restart it in one "
                     "process");
  auto array = [&](const std::string& key) -> const std::vector<double>& {
    return scalar(c.reals, key, where);
  };
  const std::size_t rows = array("x").size() / Dim;
  ParticleSet<Dim>& p = engine.particles();
  p.for_each_field([&](auto& field) { field.resize(rows); });
  unflat(array("x"), p.x, "x");
  unflat(array("X"), p.X, "X");
  unflat(array("v"), p.v, "v");
  unflat(array("F"), p.F, "F");
  if (p.half_lengths !=
      HalfLengths::none) {  // a GIMP or CPDI run's, which the engine kept when it seeded its particles
    p.l0.resize(rows);
    unflat(array("l0"), p.l0, "l0");
  }
  if (engine.transfer() == Transfer::apic) {  // an APIC run's
    p.B.resize(rows);
    unflat(array("B"), p.B, "B");
  }
  if (engine.kernel() == KernelKind::cpdi2) {  // a CPDI2 run's
    p.corners.resize(rows);
    unflat(array("corners"), p.corners, "corners");
  }
  p.m = array("m");
  p.V0 = array("V0");
  const std::vector<std::int64_t>& material = scalar(c.integers, "material", where);
  for (const auto& [key, size] :
       {std::pair{"m", p.m.size()}, std::pair{"V0", p.V0.size()}, std::pair{"material", material.size()}})
    if (size != rows) throw InputError(where + ": array '" + key + "' has the wrong size");
  for (std::size_t i = 0; i < rows; ++i) p.material[i] = static_cast<std::uint16_t>(material[i]);
  // A checkpoint written before contact fields holds particles of the one field, 0 (resized above).
  const auto field = c.integers.find("field");
  if (field != c.integers.end()) {
    if (field->second.size() != rows) throw InputError(where + ": array 'field' has the wrong size");
    const std::int64_t fields = engine.velocity_fields();
    for (std::size_t i = 0; i < rows; ++i) {
      if (field->second[i] < 0 || field->second[i] >= fields)
        throw InputError(where + ": array 'field' names a velocity field the scene does not have");
      p.field[i] = static_cast<std::uint16_t>(field->second[i]);
    }
  }
  // A checkpoint written before particles had ids holds the first particles seeded when none had left.
  const auto id = c.integers.find("id");
  if (id != c.integers.end()) {
    if (id->second.size() != p.size()) throw InputError(where + ": array 'id' has the wrong size");
    p.id = id->second;
  } else if (out.particles > 0) {
    throw InputError(where +
                     ": a checkpoint without particle ids, taken after particles left; rerun from t = 0");
  }
  engine.load(c, where);
  a.external_work = scalar(c.real_scalars, "external_work", where);
  // A checkpoint written before Coulomb walls existed had none dissipating.
  const auto dissipated = c.real_scalars.find("friction_dissipation");
  a.friction_dissipation = dissipated == c.real_scalars.end() ? 0 : dissipated->second;
  a.last_frame_time = scalar(c.real_scalars, "last_frame_time", where);
  a.error.linf = scalar(c.real_scalars, "error_linf", where);
  a.error.sum = scalar(c.real_scalars, "error_sum", where);
  a.error.sum_sq = scalar(c.real_scalars, "error_sum_sq", where);
  a.error.samples = scalar(c.integer_scalars, "error_samples", where);
}
}  // namespace detail

/// Set the engine's particles and state and the accumulators from `c`, this rank's share of a checkpoint
/// (io::read_checkpoint), on every rank; InputError prefixed with `where`, the same on every rank, when `c`
/// is not a checkpoint of this scene.
template <int Dim>
void restore(const io::CheckpointData& c, SceneEngine<Dim>& engine, Accumulators& a,
             const std::string& where) {
  const Communicator& comm = engine.communicator();
  const std::int64_t seeded = engine.particle_count();
  std::string failure;
  try {
    detail::load_share<Dim>(c, engine, a, seeded, where);
  } catch (const InputError& e) {
    failure = e.what();
  }
  if (const std::string first = first_failure(comm, failure); !first.empty()) throw InputError(first);
  std::vector<std::int64_t> rows{static_cast<std::int64_t>(engine.particles().size())};
  comm.sum(rows);
  if (rows[0] != c.integer_scalars.at("particles"))
    throw InputError(where + ": the checkpoint holds " + std::to_string(rows[0]) +
                     " particles' rows, not the " + std::to_string(c.integer_scalars.at("particles")) +
                     " it says");
  engine.take_particles();
}

}  // namespace mpm::scene_checkpoint

#pragma once
// The checkpoint of a scene run: the particle arrays, the clock, the engine's state and the run's accumulators,
// bit for bit, so that a restart ends bitwise equal to an uninterrupted run.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/scene/scene.hpp"
#include "mpm/verification/error_norms.hpp"
#include "engines.hpp"

namespace mpm::scene_checkpoint {

/// What a run accumulates besides the particles.
struct Accumulators {
  std::int64_t frames = 0;    ///< particle outputs written
  Real last_frame_time = -1;  ///< time of the last one
  Real external_work = 0;     ///< work of the loads and moving constraints since t = 0 [J]
  ErrorNorms error;           ///< the [check] error norms so far
};

/// What has left through outflow faces, into a checkpoint and back. A checkpoint written before outflow faces
/// existed holds none of it: nothing had left.
template <int Dim>
void save_outflow(const Outflow<Dim>& out, io::CheckpointData& c) {
  c.integer_scalars["outflow_particles"] = out.particles;
  c.real_scalars["outflow_mass"] = out.mass;
  c.real_scalars["outflow_kinetic_energy"] = out.kinetic_energy;
  c.real_scalars["outflow_strain_energy"] = out.strain_energy;
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
  out.strain_energy = scene_engines::entry(c.real_scalars, "outflow_strain_energy", where);
  const std::vector<double>& momentum = scene_engines::entry(c.reals, "outflow_momentum", where);
  if (momentum.size() != Dim) throw InputError(where + ": array 'outflow_momentum' has the wrong size");
  std::copy(momentum.begin(), momentum.end(), out.momentum.data());
  return out;
}

template <int Dim, class Engine>
io::CheckpointData save(const Scene& sc, const Engine& engine, const Accumulators& a) {
  using scene_engines::flat;
  const ParticleSet<Dim>& p = engine.sim().particles();
  io::CheckpointData c;
  c.texts["scene"] = sc.text;
  c.integer_scalars = {{"dim", Dim}, {"particles", static_cast<std::int64_t>(p.size())}, {"steps", engine.sim().steps()},
                       {"frames", a.frames}, {"error_samples", a.error.samples}};
  c.real_scalars = {{"time", engine.sim().time()}, {"external_work", a.external_work},
                    {"last_frame_time", a.last_frame_time}, {"error_linf", a.error.linf},
                    {"error_sum", a.error.sum}, {"error_sum_sq", a.error.sum_sq}};
  c.reals = {{"x", flat(p.x)}, {"X", flat(p.X)}, {"v", flat(p.v)}, {"F", flat(p.F)}, {"m", p.m}, {"V0", p.V0},
             {"l0", flat(p.l0)}, {"l", flat(p.l)}};
  c.integers["material"] = std::vector<std::int64_t>(p.material.begin(), p.material.end());
  c.integers["id"] = p.id;
  save_outflow(engine.sim().outflow(), c);
  engine.save(c);
  return c;
}

/// Set the engine's particles and state and the accumulators from `c`; InputError prefixed with `where` when `c`
/// is not a checkpoint of this scene.
template <int Dim, class Engine>
void restore(const io::CheckpointData& c, Engine& engine, Accumulators& a, const std::string& where) {
  using scene_engines::unflat;
  auto scalar = [&](const auto& map, const std::string& key) -> const auto& {
    auto it = map.find(key);
    if (it == map.end()) throw InputError(where + ": not a checkpoint of a scene run (no '" + key + "')");
    return it->second;
  };
  ParticleSet<Dim>& p = engine.sim().particles();
  const std::int64_t particles = scalar(c.integer_scalars, "particles");
  const Outflow<Dim> out = load_outflow<Dim>(c, where);
  if (scalar(c.integer_scalars, "dim") != Dim || particles < 0 || out.particles < 0 ||
      particles + out.particles != static_cast<std::int64_t>(p.size()))
    throw InputError(where + ": the checkpoint holds a different scene (dimension or particle count differ)");
  engine.sim().restore_outflow(static_cast<std::size_t>(particles), out);
  auto array = [&](const std::string& key) -> const std::vector<double>& { return scalar(c.reals, key); };
  unflat(array("x"), p.x, "x");
  unflat(array("X"), p.X, "X");
  unflat(array("v"), p.v, "v");
  unflat(array("F"), p.F, "F");
  unflat(array("l0"), p.l0, "l0");
  unflat(array("l"), p.l, "l");
  p.m = array("m");
  p.V0 = array("V0");
  const std::vector<std::int64_t>& mat = scalar(c.integers, "material");
  for (std::size_t i = 0; i < p.size(); ++i) p.material[i] = static_cast<std::uint16_t>(mat.at(i));
  // A checkpoint written before particles had ids holds the first particles seeded when none had left.
  const auto id = c.integers.find("id");
  if (id != c.integers.end()) {
    if (id->second.size() != p.size()) throw InputError(where + ": array 'id' has the wrong size");
    p.id = id->second;
  } else if (out.particles > 0) {
    throw InputError(where + ": a checkpoint without particle ids, taken after particles left; rerun from t = 0");
  }
  engine.load(c, where);
  a.external_work = scalar(c.real_scalars, "external_work");
  a.last_frame_time = scalar(c.real_scalars, "last_frame_time");
  a.error.linf = scalar(c.real_scalars, "error_linf");
  a.error.sum = scalar(c.real_scalars, "error_sum");
  a.error.sum_sq = scalar(c.real_scalars, "error_sum_sq");
  a.error.samples = scalar(c.integer_scalars, "error_samples");
}

}  // namespace mpm::scene_checkpoint

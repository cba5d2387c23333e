#pragma once
// The checkpoint of a scene run: the particle arrays, the clock, the engine's state and the run's accumulators,
// bit for bit, so that a restart ends bitwise equal to an uninterrupted run.
#include <algorithm>
#include <cstdint>
#include <string>

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
  const Outflow<Dim>& out = engine.sim().outflow();
  c.integer_scalars["outflow_particles"] = out.particles;
  c.real_scalars["outflow_mass"] = out.mass;
  c.real_scalars["outflow_kinetic_energy"] = out.kinetic_energy;
  c.real_scalars["outflow_strain_energy"] = out.strain_energy;
  c.reals["outflow_momentum"] = std::vector<double>(out.momentum.data(), out.momentum.data() + Dim);
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
  const std::int64_t gone = scalar(c.integer_scalars, "outflow_particles");
  if (scalar(c.integer_scalars, "dim") != Dim || particles < 0 || gone < 0 ||
      particles + gone != static_cast<std::int64_t>(p.size()))
    throw InputError(where + ": the checkpoint holds a different scene (dimension or particle count differ)");
  Outflow<Dim> out;
  out.particles = gone;
  out.mass = scalar(c.real_scalars, "outflow_mass");
  out.kinetic_energy = scalar(c.real_scalars, "outflow_kinetic_energy");
  out.strain_energy = scalar(c.real_scalars, "outflow_strain_energy");
  const std::vector<double>& momentum = scalar(c.reals, "outflow_momentum");
  if (momentum.size() != Dim) throw InputError(where + ": array 'outflow_momentum' has the wrong size");
  std::copy(momentum.begin(), momentum.end(), out.momentum.data());
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
  engine.load(c, where);
  a.external_work = scalar(c.real_scalars, "external_work");
  a.last_frame_time = scalar(c.real_scalars, "last_frame_time");
  a.error.linf = scalar(c.real_scalars, "error_linf");
  a.error.sum = scalar(c.real_scalars, "error_sum");
  a.error.sum_sq = scalar(c.real_scalars, "error_sum_sq");
  a.error.samples = scalar(c.integer_scalars, "error_samples");
}

}  // namespace mpm::scene_checkpoint

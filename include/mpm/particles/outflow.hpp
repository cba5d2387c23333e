#pragma once
/// Particles leaving through outflow faces: what they carry out, and their removal from the particle set
/// (Steffen et al. 2008, Sec. 3.4: at a free boundary material advects out of the domain).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// What has left through the outflow faces since t = 0 (per unit thickness or per radian, as the particles).
template <int Dim>
struct Outflow {
  std::int64_t particles = 0;
  Real mass = 0;                                 ///< [kg]
  Vec<Dim> momentum = Vec<Dim>::Zero();          ///< [kg m/s]
  Real kinetic_energy = 0, internal_energy = 0;  ///< 1/2 m v^2 and the engine's internal energy [J]

  /// Count particle i of p, whose internal energy is `internal`, as gone.
  void add(const ParticleSet<Dim>& p, std::size_t i, Real internal) {
    ++particles;
    mass += p.m[i];
    momentum += p.m[i] * p.v[i];
    kinetic_energy += 0.5 * p.m[i] * p.v[i].squaredNorm();
    internal_energy += internal;
  }
  /// Count the particles of one removal, their sums given (over every rank, summed exactly).
  void add_sums(std::int64_t count, Real m, const Vec<Dim>& mv, Real kinetic, Real internal) {
    particles += count;
    mass += m;
    momentum += mv;
    kinetic_energy += kinetic;
    internal_energy += internal;
  }
};

/// The particles (ascending) that lie beyond an outflow face of g.
template <int Dim>
std::vector<std::size_t> beyond_outflow(const ParticleSet<Dim>& p, const GridGeometry<Dim>& g) {
  std::vector<std::size_t> gone;
  bool any = false;
  for (bool f : g.outflow) any = any || f;
  if (!any) return gone;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (g.beyond_outflow(p.x[i])) gone.push_back(i);
  return gone;
}

/// Remove the entries at `gone` (ascending) from a, keeping the order of the rest; arrays shorter than the
/// particle set (unused, empty) are left as they are.
template <class T>
void erase_at(std::vector<T>& a, const std::vector<std::size_t>& gone, std::size_t particles) {
  if (a.size() != particles) return;
  std::size_t out = 0, next = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (next < gone.size() && gone[next] == i) {
      ++next;
      continue;
    }
    if (out != i) a[out] = std::move(a[i]);
    ++out;
  }
  a.resize(out);
}

/// Remove the particles at `gone` (ascending) from every array of p and its material state.
template <int Dim>
void erase_particles(ParticleSet<Dim>& p, const std::vector<std::size_t>& gone) {
  const std::size_t n = p.size();
  p.for_each_array([&](auto& a) { erase_at(a, gone, n); });
}

}  // namespace mpm

#pragma once
/// Reordering per-particle arrays: new entry k is old entry order[k].
#include <cstdint>
#include <utility>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// a[k] = a_old[order[k]] for an array of order.size() entries; arrays of another size (unused, empty) are left
/// as they are. The copy goes through a buffer kept per element type and thread, so repeated reorders do not allocate.
template <class T>
void gather_by(std::vector<T>& a, const std::vector<std::int32_t>& order) {
  if (a.size() != order.size()) return;
  static thread_local std::vector<T> kept;
  std::vector<T>& buffer = kept;  // this thread's, named for the loop's threads
  buffer.resize(a.size());
  parallel_for(static_cast<std::ptrdiff_t>(a.size()), [&](std::ptrdiff_t k) { buffer[k] = a[order[k]]; });
  std::swap(a, buffer);
}

/// Reorder every array of p and its material state.
template <int Dim>
void reorder_particles(ParticleSet<Dim>& p, const std::vector<std::int32_t>& order) {
  p.for_each_array([&](auto& a) { gather_by(a, order); });
}

}  // namespace mpm

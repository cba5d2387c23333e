#pragma once
/// Particles as bytes, to move them between ranks: every field of a particle, its material state's too when the
/// set carries one, in the order of ParticleSet::for_each_array.
#include <cstddef>
#include <cstring>
#include <vector>

#include "mpm/particles/particles.hpp"

namespace mpm {

/// Append particle i's fields to `bytes`; `with_state`: the set carries a material state (MaterialState).
template <int Dim>
void pack_particle(ParticleSet<Dim>& p, std::size_t i, bool with_state, std::vector<std::byte>& bytes) {
  const auto append = [&](auto& a) {
    const auto* from = reinterpret_cast<const std::byte*>(&a[i]);
    bytes.insert(bytes.end(), from, from + sizeof(a[i]));
  };
  if (with_state)
    p.for_each_array(append);
  else
    p.for_each_field(append);
}

/// Append the particles packed in `bytes` (pack_particle, the same with_state) to p.
template <int Dim>
void unpack_particles(const std::vector<std::byte>& bytes, bool with_state, ParticleSet<Dim>& p) {
  std::size_t per = 0;
  const auto count = [&](auto& a) { per += sizeof(a[0]); };
  if (with_state)
    p.for_each_array(count);
  else
    p.for_each_field(count);
  const std::size_t n = bytes.size() / per;
  std::size_t at = 0;
  const auto take = [&](auto& a) {
    const std::size_t first = a.size();
    a.resize(first + n);
    for (std::size_t k = 0; k < n; ++k)
      std::memcpy(static_cast<void*>(&a[first + k]), &bytes[at + k * per], sizeof(a[0]));
    at += sizeof(a[0]);
  };
  if (with_state)
    p.for_each_array(take);
  else
    p.for_each_field(take);
}

}  // namespace mpm

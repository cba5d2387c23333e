#pragma once
/// Particles as bytes, to move them between ranks: every field of a particle, and its material state's, APIC
/// matrix, CPDI2 corners and half-lengths when the set carries them, in the order of
/// ParticleSet::for_each_array.
#include <cstddef>
#include <cstring>
#include <vector>

#include "mpm/particles/particles.hpp"

namespace mpm {

/// The optional arrays a set carries, the same on every rank of a run.
struct PackedArrays {
  bool state = false;         ///< the material state (MaterialState)
  bool affine = false;        ///< APIC's B_p
  bool corners = false;       ///< CPDI2's domain corners
  bool half_lengths = false;  ///< l_p^0 (GIMP and CPDI)
};

/// fn(array) for every array `with` names, in the order of ParticleSet::for_each_array.
template <int Dim, class Fn>
void for_each_packed_array(ParticleSet<Dim>& p, PackedArrays with, Fn&& fn) {
  p.for_each_field(fn);
  if (with.state) p.for_each_state_array(fn);
  if (with.affine) fn(p.B);
  if (with.corners) fn(p.corners);
  if (with.half_lengths) fn(p.l0);
}

/// Append particle i's fields to `bytes`.
template <int Dim>
void pack_particle(ParticleSet<Dim>& p, std::size_t i, PackedArrays with, std::vector<std::byte>& bytes) {
  for_each_packed_array(p, with, [&](auto& a) {
    const auto* from = reinterpret_cast<const std::byte*>(&a[i]);
    bytes.insert(bytes.end(), from, from + sizeof(a[i]));
  });
}

/// Append the particles packed in `bytes` (pack_particle, the same `with`) to p.
template <int Dim>
void unpack_particles(const std::vector<std::byte>& bytes, PackedArrays with, ParticleSet<Dim>& p) {
  std::size_t per = 0;
  for_each_packed_array(p, with, [&](auto& a) { per += sizeof(a[0]); });
  const std::size_t n = bytes.size() / per;
  std::size_t at = 0;
  for_each_packed_array(p, with, [&](auto& a) {
    const std::size_t first = a.size();
    a.resize(first + n);
    for (std::size_t k = 0; k < n; ++k)
      std::memcpy(static_cast<void*>(&a[first + k]), &bytes[at + k * per], sizeof(a[0]));
    at += sizeof(a[0]);
  });
}

}  // namespace mpm

#pragma once
// The lattice shapes of bodies and rigid bodies: where a shape lies, whether a point lies in it, and its
// points.
#include <cstdint>
#include <utility>
#include <vector>

#include "mpm/boundary/rigid_body.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {

template <int Dim>
Vec<Dim> to_vec(const std::vector<double>& v) {
  Vec<Dim> out;
  for (int d = 0; d < Dim; ++d) out[d] = v[d];
  return out;
}

/// The points of a shape's lattice (every shape but a file), each of volume s^Dim (s = h / ppc), density
/// `density` and material `material` (reference positions; ids count on from `p`'s).
template <int Dim>
void fill_shape(const Scene& sc, const SceneShape& shape, Real density, std::uint16_t material,
                ParticleSet<Dim>& p);

/// The points of body b's combined shape: those of the lattice a box from the grid's lo would have that lie
/// in its shape or one of b.add, in all of b.intersect and in none of b.subtract.
template <int Dim>
void fill_combined(const Scene& sc, const SceneBody& b, Real density, std::uint16_t material,
                   ParticleSet<Dim>& p);

/// The outward unit normal of a lattice shape's surface at the point nearest x (the gradient of its signed
/// distance; on the surface, the face's normal): boxes, disks, spheres, rings, polygons and triangulated
/// surfaces (SurfaceNormal, which keeps state between calls: one caller at a time).
template <int Dim>
OutwardNormalFn<Dim> outward_normal_of(const SceneShape& shape);

}  // namespace mpm

#pragma once
/// A rigid body's description: material points moving at a prescribed velocity that impose it on every node
/// they touch (no-slip contact through the single velocity field, Sulsky & Kaul 2004 Secs 3.1.1 and 3.2.7),
/// in both engines. What a run does with them is RigidBodies (boundary/rigid_bodies.hpp).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

template <int Dim>
constexpr std::array<bool, Dim> filled(bool value) {
  std::array<bool, Dim> a{};
  a.fill(value);
  return a;
}

/// The outward unit normal of a body's surface at the point nearest x [-].
template <int Dim>
using OutwardNormalFn = std::function<Vec<Dim>(const Vec<Dim>& x)>;

template <int Dim>
struct RigidBody {
  std::string name;
  std::vector<Vec<Dim>> points;             ///< material point positions at t = 0 [m]
  Vec<Dim> half_length = Vec<Dim>::Zero();  ///< GIMP half-lengths of its points [m]
  VelocityFn<Dim> velocity;                 ///< v(t) [m/s]
  /// Components the body imposes: all (no-slip contact, the default), or some (free slip along the others).
  std::array<bool, Dim> imposes = filled<Dim>(true);
  /// >= 0: a Coulomb body instead (coulomb_contact, contact/coulomb.hpp), whose normal at a node is the
  /// gradient of its points' shape functions there; the material may leave it and slides along it against
  /// friction.
  Real friction = -1;
  /// A Coulomb body's normal from the surface it models instead (the shape's, at the body's position at t =
  /// 0: evaluated at a node moved back by the body's displacement), so that a slab at any angle meets the
  /// material along its own normal; empty: from its points' shape-function gradients.
  OutwardNormalFn<Dim> outward{};
  /// Whether the body holds the nodes inside its box [lo, hi] (moved with it) rather than every node its
  /// points touch: a footing or platen whose width is its box's, not the box's widened by the kernel's
  /// support.
  bool holds_inside = false;
  Vec<Dim> lo = Vec<Dim>::Zero(), hi = Vec<Dim>::Zero();  ///< the box at t = 0 [m] (used when holds_inside)
};

}  // namespace mpm

#pragma once
/// The particles both engines are given, checked and started the same way: one set of messages, the
/// axisymmetric per-radian scaling, and V = V0 det F.
#include <cstdint>
#include <string>
#include <vector>

#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/kernel_kind.hpp"

namespace mpm {

/// A number with 9 significant digits, for messages ("-1e+308", not std::to_string's 309 digits).
std::string format_number(Real x);

/// A point as "(x, y)" with 9 significant digits, for messages.
template <int Dim>
std::string format_point(const Vec<Dim>& x);

/// Check every particle an engine is given and start it: inside the grid g, positive mass and volume, a
/// material of the table, a velocity field below `fields`, a finite velocity, F = I for the rate-form
/// materials, det F > 0, the kernel's half-length bounds; in axisymmetry a positive radius, and mass and
/// volume taken per radian (m_p = rho r_p A_p); then V = V0 det F. Throws InputError naming the particle
/// ("particle 12 at (0.1, 0.2) lies outside the grid ..."). Returns the smallest mass. The particles'
/// half-lengths must be set (ParticleSet:: half_lengths) first.
template <int Dim>
Real start_particles(ParticleSet<Dim>& p, const std::vector<Material>& materials, KernelKind kernel,
                     const GridGeometry<Dim>& g, bool axisymmetric, int fields);

}  // namespace mpm

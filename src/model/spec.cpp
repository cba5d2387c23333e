#include "mpm/model/spec.hpp"

#include <cmath>

#include "mpm/core/errors.hpp"

namespace mpm {

template <int Dim>
void validate_model(const ModelSpec<Dim>& s, const std::string& at) {
  require(std::isfinite(s.h) && s.h > 0, at + "grid.h: cell width must be positive");
  for (int d = 0; d < Dim; ++d) require(s.cells[d] >= 1, at + "grid.cells: every axis needs at least 1 cell");
  require(s.grid_lo.allFinite(), at + "grid.lo: must be finite");
  require(Dim == 2 || s.geometry == Geometry::plane_strain,
          at + "simulation.geometry: plane stress and axisymmetry are 2-D models");
  require(s.geometry != Geometry::axisymmetric || s.grid_lo[0] >= 0,
          at + "grid.lo: an axisymmetric grid must lie at radius x >= 0");
  validate_faces<Dim>(s.boundary, s.cells, s.geometry, s.grid_lo[0], at);
  validate_clamped_cells<Dim>(s.kernel, s.boundary, s.cells, at);
  require(!s.materials.empty(), at + "materials: at least one material is required");
  for (std::size_t k = 0; k < s.materials.size(); ++k)
    validate(s.materials[k], at + "materials[" + std::to_string(k) + "]", Dim, s.geometry);
  for (const RigidBody<Dim>& b : s.rigid_bodies) {
    require(!b.points.empty(), at + "rigid body '" + b.name + "': has no points");
    require(static_cast<bool>(b.velocity), at + "rigid body '" + b.name + "': needs a velocity");
    require(!std::isnan(b.friction), at + "rigid body '" + b.name + "': friction must be a number");
  }
  require(s.gravity.allFinite(), at + "gravity: must be finite");
  require(s.flip_fraction >= 0 && s.flip_fraction <= 1,
          at + "simulation.flip_fraction: expected a number in [0, 1]");
  require(s.transfer != Transfer::apic || s.flip_fraction == 1,
          at + "simulation.flip_fraction: applies to transfer = \"flip\" only");
}

template void validate_model<1>(const ModelSpec<1>&, const std::string&);
template void validate_model<2>(const ModelSpec<2>&, const std::string&);
template void validate_model<3>(const ModelSpec<3>&, const std::string&);

}  // namespace mpm

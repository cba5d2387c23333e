#pragma once
// The particle files of file bodies: the header that names their columns, and their rows.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "mpm/particles/particles.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {

/// What a column of a particle file holds.
struct ParticleColumn {
  enum class Role { position, volume, material, velocity, stress, plastic_strain, internal } role;
  /// the axis of a position or velocity, the SymTensor<3> index of a stress, the InternalState column of a
  /// law's internal variable
  int component = 0;
};

/// The columns of a particle file: named by its header (line 1, when it is not all numbers), or x, y, [z,]
/// volume in order without one; a law's internal variable by its name. Throws InputError "FILE:1: ..." for a
/// column that is not known, repeated, or a position or the volume missing.
std::vector<ParticleColumn> particle_file_columns(const std::filesystem::path& file, int dim,
                                                  const std::vector<Material>& materials);

/// The half-lengths of a particle given as a point and a volume V (a file's row, a mesh's Gauss point): those
/// of a cube of volume V, V^(1/dim) / 2 per axis. A cube a cell of width h wide (one particle per cell), or
/// half a cell, is that within round-off: its half-length is h / 2 or h / 4 exactly, not the root's last bit
/// above the GIMP kernels' bound h / 2.
template <int Dim>
Vec<Dim> cube_half_lengths(Real V, Real h) {
  Real l = 0.5 * std::pow(V, 1.0 / Dim);
  for (const Real exact : {0.5 * h, 0.25 * h})
    if (std::abs(l - exact) <= 1e-12 * exact) l = exact;
  return Vec<Dim>::Constant(l);
}

/// Whether the columns hold `role`.
bool has_column(const std::vector<ParticleColumn>& columns, ParticleColumn::Role role);

/// The rows of body b's particle file appended to p (reference positions; mass rho V and cube_half_lengths;
/// the material, velocity, stress, plastic strain and a law's internal variables of the columns that give
/// them). A
/// bad row throws "FILE:LINE: row of KEY: ..." (`key` names the scene key).
template <int Dim>
void read_particle_rows(const Scene& sc, const SceneBody& b, const std::string& key, ParticleSet<Dim>& p);

}  // namespace mpm

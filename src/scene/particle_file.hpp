#pragma once
// The particle files of file bodies: the header that names their columns, and their rows.
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
/// volume in order without one. Throws InputError "FILE:1: ..." for a column that is not known (the law's
/// internal variables included: they start from the particle's stress), repeated, or a position or the
/// volume missing.
std::vector<ParticleColumn> particle_file_columns(const std::filesystem::path& file, int dim,
                                                  const std::vector<Material>& materials);

/// Whether the columns hold `role`.
bool has_column(const std::vector<ParticleColumn>& columns, ParticleColumn::Role role);

/// The rows of body b's particle file appended to p (reference positions; mass rho V and half-length
/// V^(1/dim)/2 per axis; the material, velocity, stress and plastic strain of the columns that give them). A
/// bad row throws "FILE:LINE: row of KEY: ..." (`key` names the scene key).
template <int Dim>
void read_particle_rows(const Scene& sc, const SceneBody& b, const std::string& key, ParticleSet<Dim>& p);

}  // namespace mpm

#pragma once
/// Named columns of numbers from an HDF5 file: the particle files' second format (docs/scene-format.md,
/// "Particle files").
#include <filesystem>
#include <string>
#include <vector>

namespace mpm::io {

/// The 1-D datasets of numbers (integer or floating point) at the root of an HDF5 file, in name order, each
/// read as doubles.
struct NamedColumns {
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
};

/// Whether `file` names an HDF5 particle file: its extension is .h5 or .hdf5.
bool is_hdf5_file(const std::filesystem::path& file);

/// Read every dataset at the root of `file`. Throws InputError "FILE: ..." when the file cannot be read as
/// HDF5, holds no dataset, or a member is not a 1-D dataset of numbers or holds another number of values than
/// the first.
NamedColumns read_hdf5_columns(const std::filesystem::path& file);

}  // namespace mpm::io

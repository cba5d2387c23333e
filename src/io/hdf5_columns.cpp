#include "mpm/io/hdf5_columns.hpp"

#include "checkpoint_hdf5.hpp"
#include "mpm/core/errors.hpp"

namespace mpm::io {

using namespace hdf5;

bool is_hdf5_file(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".h5" || ext == ".hdf5";
}

NamedColumns read_hdf5_columns(const std::filesystem::path& file) {
  const SilenceErrors quiet;
  try {
    Handle fapl = file_access();
    Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose, "cannot be read as HDF5");
    Handle root(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, "has no root group");
    NamedColumns out;
    for (const std::string& name : member_names(root.get(), "the root group")) {
      const std::string what = "dataset '" + name + "'";
      Handle set(H5Dopen2(root.get(), name.c_str(), H5P_DEFAULT), H5Dclose, what + " is not a dataset");
      Handle type(H5Dget_type(set.get()), H5Tclose, "cannot read the type of " + what);
      const H5T_class_t cls = H5Tget_class(type.get());
      Handle space(H5Dget_space(set.get()), H5Sclose, "cannot read the shape of " + what);
      if ((cls != H5T_INTEGER && cls != H5T_FLOAT) || H5Sget_simple_extent_type(space.get()) != H5S_SIMPLE ||
          H5Sget_simple_extent_ndims(space.get()) != 1)
        throw Failure(what + " is not a 1-D array of numbers");
      const hssize_t n = H5Sget_simple_extent_npoints(space.get());
      if (n < 0) throw Failure("cannot read the size of " + what);
      if (!out.values.empty() && static_cast<std::size_t>(n) != out.values[0].size())
        throw Failure(what + " holds " + std::to_string(n) + " values, '" + out.names[0] + "' " +
                      std::to_string(out.values[0].size()));
      std::vector<double> values(static_cast<std::size_t>(n));
      if (n > 0)
        check(H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
              "cannot read " + what);
      out.names.push_back(name);
      out.values.push_back(std::move(values));
    }
    if (out.names.empty()) throw Failure("holds no dataset at its root");
    return out;
  } catch (const Failure& e) {
    throw InputError(file.string() + ": " + e.what());
  }
}

}  // namespace mpm::io

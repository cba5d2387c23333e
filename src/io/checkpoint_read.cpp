/// Reading a checkpoint (layout in include/mpm/io/checkpoint.hpp): the seal first, then HDF5. On several
/// ranks each rank opens the file itself and reads its share of the rows; rank 0 checks the seal for all.
#include <algorithm>
#include <cstring>

#include "checkpoint_hdf5.hpp"
#include "checkpoint_seal.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/io/checkpoint.hpp"

namespace mpm::io {

namespace fs = std::filesystem;
using namespace hdf5;

namespace {

/// This rank's share of the rows: rank r of R reads rows [n r / R, n (r + 1) / R) of the n in the file.
struct Share {
  std::int64_t rank = 0, ranks = 1;
  std::int64_t rows = -1;  ///< n, once an array of rows was read
};

/// Calls fn(name, path, dataset) for every member of the group at `group_path`; a missing group holds
/// nothing.
template <class Fn>
void for_each_dataset(hid_t file, const char* group_path, Fn&& fn) {
  const htri_t exists = H5Lexists(file, group_path, H5P_DEFAULT);
  if (exists < 0) throw Failure(std::string("cannot look up ") + group_path);
  if (exists == 0) return;
  Handle group(H5Gopen2(file, group_path, H5P_DEFAULT), H5Gclose,
               std::string(group_path) + " is not a group");
  for (const std::string& name : member_names(group.get(), group_path)) {
    const std::string path = std::string(group_path) + "/" + name;
    Handle set(H5Dopen2(group.get(), name.c_str(), H5P_DEFAULT), H5Dclose, path + " is not a dataset");
    fn(name, path, set.get());
  }
}

void expect_class(hid_t set, H5T_class_t expected, const std::string& path, const char* what) {
  Handle type(H5Dget_type(set), H5Tclose, "cannot get the type of " + path);
  if (H5Tget_class(type.get()) != expected) throw Failure(path + " does not hold " + what);
}

/// The row width of an array of rows (at least 1), 0 for any other array.
std::int64_t row_width(hid_t set, const std::string& path) {
  const htri_t has = H5Aexists(set, row_width_attribute);
  if (has < 0) throw Failure("cannot look up the attributes of " + path);
  if (has == 0) return 0;
  Handle attribute(H5Aopen(set, row_width_attribute, H5P_DEFAULT), H5Aclose,
                   "cannot open the row width of " + path);
  Handle type(H5Aget_type(attribute.get()), H5Tclose, "cannot get the type of the row width of " + path);
  Handle space(H5Aget_space(attribute.get()), H5Sclose,
               "cannot get the dataspace of the row width of " + path);
  if (H5Tget_class(type.get()) != H5T_INTEGER || H5Sget_simple_extent_type(space.get()) != H5S_SCALAR)
    throw Failure("the row width of " + path + " is not an integer");
  std::int64_t width = 0;
  check(H5Aread(attribute.get(), H5T_NATIVE_INT64, &width), "cannot read the row width of " + path);
  if (width < 1) throw Failure("the row width of " + path + " is " + std::to_string(width));
  return width;
}

/// A 1-D array, whole; of an array of rows, this rank's share (its width into row_widths).
template <class T>
std::vector<T> read_array(hid_t set, const std::string& name, const std::string& path, H5T_class_t cls,
                          hid_t mem_type, const char* what, Share& share, CheckpointData& data) {
  expect_class(set, cls, path, what);
  Handle space(H5Dget_space(set), H5Sclose, "cannot get the dataspace of " + path);
  if (H5Sget_simple_extent_type(space.get()) != H5S_SIMPLE || H5Sget_simple_extent_ndims(space.get()) != 1)
    throw Failure(path + " is not a 1-D array");
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw Failure("cannot get the size of " + path);
  hsize_t first = 0, count = static_cast<hsize_t>(n);
  if (const std::int64_t width = row_width(set, path); width > 0) {
    if (n % width != 0)
      throw Failure(path + " of " + std::to_string(n) + " values is not rows of " + std::to_string(width));
    const std::int64_t rows = n / width;
    if (share.rows >= 0 && rows != share.rows)
      throw Failure(path + " holds another number of rows than the others");
    share.rows = rows;
    const std::int64_t begin = rows * share.rank / share.ranks, end = rows * (share.rank + 1) / share.ranks;
    first = static_cast<hsize_t>(begin * width);
    count = static_cast<hsize_t>((end - begin) * width);
    data.row_widths[name] = width;
  }
  std::vector<T> values(count);
  if (count == 0) return values;
  const hsize_t start[1] = {first}, size[1] = {count};
  check(H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, size, nullptr),
        "cannot select in " + path);
  Handle mem(H5Screate_simple(1, size, nullptr), H5Sclose, "cannot create memory dataspace for " + path);
  check(H5Dread(set, mem_type, mem.get(), space.get(), H5P_DEFAULT, values.data()), "cannot read " + path);
  return values;
}

template <class T>
T read_scalar(hid_t set, const std::string& path, H5T_class_t cls, hid_t mem_type, const char* what) {
  expect_class(set, cls, path, what);
  Handle space(H5Dget_space(set), H5Sclose, "cannot get the dataspace of " + path);
  if (H5Sget_simple_extent_type(space.get()) != H5S_SCALAR) throw Failure(path + " is not a scalar");
  T value{};
  check(H5Dread(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value), "cannot read " + path);
  return value;
}

/// The size in bytes of the fixed-length string type `type`; throws unless it is one.
std::size_t fixed_string_size(hid_t type, const std::string& path) {
  if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) != 0)
    throw Failure(path + " is not a fixed-length string");
  return H5Tget_size(type);
}

/// Bytes read from a string type padded other than NULLPAD end at the first NUL.
void trim_padding(hid_t type, std::string& text) {
  if (H5Tget_strpad(type) != H5T_STR_NULLPAD) text.resize(std::strlen(text.c_str()));
}

std::string read_text(hid_t set, const std::string& path) {
  Handle type(H5Dget_type(set), H5Tclose, "cannot get the type of " + path);
  const std::size_t size = fixed_string_size(type.get(), path);
  Handle space(H5Dget_space(set), H5Sclose, "cannot get the dataspace of " + path);
  const H5S_class_t cls = H5Sget_simple_extent_type(space.get());
  if (cls == H5S_NULL) return {};
  if (cls != H5S_SCALAR) throw Failure(path + " is not a scalar string");
  Handle mem = string_type(size);
  std::string text(size, '\0');
  check(H5Dread(set, mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()), "cannot read " + path);
  trim_padding(type.get(), text);
  return text;
}

/// Throws unless the root carries format = "mpm-checkpoint" and format_version = 1.
void check_marker(hid_t file) {
  if (H5Aexists(file, "format") <= 0) throw Failure("not an mpm checkpoint (no 'format' attribute)");
  Handle fmt(H5Aopen(file, "format", H5P_DEFAULT), H5Aclose, "cannot open attribute format");
  Handle type(H5Aget_type(fmt.get()), H5Tclose, "cannot get the type of attribute format");
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) != 0)
    throw Failure("not an mpm checkpoint ('format' is not a fixed-length string)");
  const std::size_t size = H5Tget_size(type.get());
  Handle mem = string_type(size);
  std::string format(size, '\0');
  check(H5Aread(fmt.get(), mem.get(), format.data()), "cannot read attribute format");
  trim_padding(type.get(), format);
  if (format != checkpoint_format)
    throw Failure("not an mpm checkpoint (format is '" + format + "', expected '" + checkpoint_format + "')");

  if (H5Aexists(file, "format_version") <= 0) throw Failure("no 'format_version' attribute");
  Handle version(H5Aopen(file, "format_version", H5P_DEFAULT), H5Aclose,
                 "cannot open attribute format_version");
  Handle vtype(H5Aget_type(version.get()), H5Tclose, "cannot get the type of attribute format_version");
  if (H5Tget_class(vtype.get()) != H5T_INTEGER) throw Failure("'format_version' is not an integer");
  std::int64_t v = 0;
  check(H5Aread(version.get(), H5T_NATIVE_INT64, &v), "cannot read attribute format_version");
  if (v != checkpoint_format_version)
    throw Failure("format_version " + std::to_string(v) + " is not supported (this build reads " +
                  std::to_string(checkpoint_format_version) + ")");
}

CheckpointData read_hdf5(const fs::path& path, Share share) {
  Handle fapl = file_access();
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose, "cannot open as HDF5");
  check_marker(file.get());
  CheckpointData data;
  for_each_dataset(file.get(), reals_group, [&](const std::string& name, const std::string& p, hid_t set) {
    data.reals[name] = read_array<double>(set, name, p, H5T_FLOAT, H5T_NATIVE_DOUBLE, "reals", share, data);
  });
  for_each_dataset(file.get(), integers_group, [&](const std::string& name, const std::string& p, hid_t set) {
    data.integers[name] =
        read_array<std::int64_t>(set, name, p, H5T_INTEGER, H5T_NATIVE_INT64, "integers", share, data);
  });
  for_each_dataset(
      file.get(), real_scalars_group, [&](const std::string& name, const std::string& p, hid_t set) {
        data.real_scalars[name] = read_scalar<double>(set, p, H5T_FLOAT, H5T_NATIVE_DOUBLE, "a real");
      });
  for_each_dataset(file.get(), integer_scalars_group,
                   [&](const std::string& name, const std::string& p, hid_t set) {
                     data.integer_scalars[name] =
                         read_scalar<std::int64_t>(set, p, H5T_INTEGER, H5T_NATIVE_INT64, "an integer");
                   });
  for_each_dataset(file.get(), texts_group, [&](const std::string& name, const std::string& p, hid_t set) {
    data.texts[name] = read_text(set, p);
  });
  return data;
}

/// Why the file cannot be handed to HDF5 (empty: it can): missing, not a file, or not sealed as written.
/// HDF5 reads the file only if it is exactly as written: HDF5 1.10 may allocate gigabytes, leak, or print to
/// stderr at exit on a corrupt file (docs/hardening.md), so an unsealed one is not handed to it either.
std::string refusal(const fs::path& file) {
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (!fs::exists(status)) return "no such file";
  if (!fs::is_regular_file(status)) return "not a regular file";
  std::string why;
  switch (seal::verify(file, why)) {
    case seal::Verdict::foreign:
      return "not an HDF5 file";
    case seal::Verdict::unsealed:
      return "an HDF5 file without the checkpoint seal (written by another program, or by mpm before "
             "checkpoints "
             "were sealed): not read";
    case seal::Verdict::corrupt:
      return "corrupt: " + why;
    case seal::Verdict::sealed:
      break;
  }
  return {};
}

}  // namespace

CheckpointData read_checkpoint(const fs::path& file) {
  return read_checkpoint(file, one_process());
}

CheckpointData read_checkpoint(const fs::path& file, const Communicator& comm) {
  const auto fail = [&](const std::string& what) {
    throw InputError("checkpoint " + file.string() + ": " + what);
  };
  if (const std::string why = broadcast_text(comm, comm.rank() == 0 ? refusal(file) : "", 0); !why.empty())
    fail(why);
  const SilenceErrors silence;
  CheckpointData data;
  std::string failure;
  try {
    const htri_t is_hdf5 = H5Fis_hdf5(file.c_str());
    if (is_hdf5 < 0) throw Failure("cannot be opened");
    if (is_hdf5 == 0) throw Failure("not an HDF5 file");
    data = read_hdf5(file, Share{comm.rank(), comm.size()});
  } catch (const Failure& e) {
    failure = e.what();
  }
  if (const std::string first = first_failure(comm, failure); !first.empty()) fail(first);
  return data;
}

}  // namespace mpm::io

/// Writing a checkpoint (layout in include/mpm/io/checkpoint.hpp): to a temporary file in the same directory,
/// flushed, sealed and fsynced, then renamed over the target (rename(2) is atomic within a file system) and
/// the directory fsynced, so a reader sees either the old checkpoint or the new one. Divided between ranks,
/// every rank writes its rows into the one temporary file through MPI-IO, and rank 0 seals and renames it.
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "checkpoint_hdf5.hpp"
#include "checkpoint_seal.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/io/checkpoint.hpp"

namespace mpm::io {

namespace fs = std::filesystem;
using namespace hdf5;

namespace {

/// Where this rank's rows go in the file: rows [first, first + count) of `total`. The root writes what every
/// rank holds alike; `collective`: the file is open on every rank (MPI-IO), and every rank takes part in
/// every write, selecting nothing where it has nothing to write.
struct Part {
  std::int64_t first = 0, count = 0, total = 0;
  bool root = true;
  bool collective = false;
};

void check_name(const std::string& kind, const std::string& name) {
  if (name.empty() || name == "." || name.find('/') != std::string::npos)
    throw Failure("invalid " + kind + " name '" + name + "' (must be non-empty, not '.', without '/')");
}

void check_names(const CheckpointData& data) {
  for (const auto& entry : data.reals) check_name("real array", entry.first);
  for (const auto& entry : data.integers) check_name("integer array", entry.first);
  for (const auto& entry : data.real_scalars) check_name("real scalar", entry.first);
  for (const auto& entry : data.integer_scalars) check_name("integer scalar", entry.first);
  for (const auto& entry : data.texts) check_name("text", entry.first);
}

/// The rows this rank holds: size / width of every array of rows, which must agree.
std::int64_t own_rows(const CheckpointData& data) {
  std::int64_t rows = -1;
  for (const auto& [name, width] : data.row_widths) {
    const auto real = data.reals.find(name);
    const auto integer = data.integers.find(name);
    if (real == data.reals.end() && integer == data.integers.end())
      throw Failure("row array '" + name + "' is neither a real nor an integer array");
    const std::size_t size = real != data.reals.end() ? real->second.size() : integer->second.size();
    if (width < 1 || size % static_cast<std::size_t>(width) != 0)
      throw Failure("row array '" + name + "' of " + std::to_string(size) + " values is not rows of " +
                    std::to_string(width));
    const auto n = static_cast<std::int64_t>(size / static_cast<std::size_t>(width));
    if (rows >= 0 && n != rows) throw Failure("row arrays of different lengths ('" + name + "')");
    rows = n;
  }
  return std::max<std::int64_t>(rows, 0);
}

Handle create_group(hid_t file, const char* path) {
  return Handle(H5Gcreate2(file, path, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                std::string("cannot create group ") + path);
}

Handle create_dataset(hid_t group, const std::string& path, const std::string& name, hid_t file_type,
                      hid_t space) {
  return Handle(H5Dcreate2(group, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                H5Dclose, "cannot create dataset " + path);
}

/// Data transfer properties: collective MPI-IO when the file is open on every rank.
Handle transfer(const Part& part) {
  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "cannot create transfer properties");
#ifdef MPM_COLLECTIVE_CHECKPOINTS
  if (part.collective)
    check(H5Pset_dxpl_mpio(dxpl.get(), H5FD_MPIO_COLLECTIVE), "cannot set collective transfer");
#else
  (void)part;
#endif
  return dxpl;
}

/// Write `values` [first, first + count) of a dataset of `total`: memory and file selections of `count`
/// values, or none.
void write_selection(hid_t set, hid_t file_space, hid_t mem_type, const void* values, hsize_t first,
                     hsize_t count, hid_t dxpl, const std::string& path) {
  const hsize_t size[1] = {count > 0 ? count : 1};
  Handle mem(H5Screate_simple(1, size, nullptr), H5Sclose, "cannot create memory dataspace for " + path);
  if (count > 0) {
    const hsize_t start[1] = {first};
    check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, size, nullptr),
          "cannot select in " + path);
  } else {
    check(H5Sselect_none(file_space), "cannot select in " + path);
    check(H5Sselect_none(mem.get()), "cannot select in " + path);
  }
  check(H5Dwrite(set, mem_type, mem.get(), file_space, dxpl, values), "cannot write " + path);
}

/// A 1-D dataset; an array of rows gets this rank's rows at its place and the attribute row_width, any other
/// array is written by the root. Zero-length arrays are a dataspace of extent 0 and nothing written.
template <class T>
void write_array(hid_t group, const std::string& group_path, const std::string& name, hid_t file_type,
                 hid_t mem_type, const std::vector<T>& values, const CheckpointData& data, const Part& part) {
  const std::string path = group_path + "/" + name;
  const auto row = data.row_widths.find(name);
  const std::int64_t width = row == data.row_widths.end() ? 0 : row->second;
  const hsize_t total = width > 0 ? static_cast<hsize_t>(part.total * width) : values.size();
  const hsize_t first = width > 0 ? static_cast<hsize_t>(part.first * width) : 0;
  const hsize_t count = width > 0 || part.root ? values.size() : 0;
  const hsize_t dims[1] = {total};
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "cannot create dataspace for " + path);
  Handle set = create_dataset(group, path, name, file_type, space.get());
  if (width > 0) {
    Handle scalar(H5Screate(H5S_SCALAR), H5Sclose, "cannot create dataspace for " + path);
    Handle attribute(
        H5Acreate2(set.get(), row_width_attribute, H5T_STD_I64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT),
        H5Aclose, "cannot create the row width of " + path);
    check(H5Awrite(attribute.get(), H5T_NATIVE_INT64, &width), "cannot write the row width of " + path);
  }
  if (total == 0) return;
  Handle dxpl = transfer(part);
  write_selection(set.get(), space.get(), mem_type, values.data(), first, count, dxpl.get(), path);
}

/// A scalar dataset of `file_type` over `space` (scalar or null), written by the root.
void write_single(hid_t group, const std::string& path, const std::string& name, hid_t file_type,
                  hid_t mem_type, H5S_class_t space_class, const void* value, const Part& part) {
  Handle space(H5Screate(space_class), H5Sclose, "cannot create dataspace for " + path);
  Handle set = create_dataset(group, path, name, file_type, space.get());
  if (space_class == H5S_NULL) return;
  Handle mem(H5Screate(H5S_SCALAR), H5Sclose, "cannot create dataspace for " + path);
  if (!part.root) {
    check(H5Sselect_none(space.get()), "cannot select in " + path);
    check(H5Sselect_none(mem.get()), "cannot select in " + path);
  }
  Handle dxpl = transfer(part);
  check(H5Dwrite(set.get(), mem_type, mem.get(), space.get(), dxpl.get(), value), "cannot write " + path);
}

void write_root_attributes(hid_t file) {
  const std::string format = checkpoint_format;
  Handle type = string_type(format.size());
  Handle scalar(H5Screate(H5S_SCALAR), H5Sclose, "cannot create dataspace for attributes");
  Handle fmt(H5Acreate2(file, "format", type.get(), scalar.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
             "cannot create attribute format");
  check(H5Awrite(fmt.get(), type.get(), format.data()), "cannot write attribute format");
  Handle version(H5Acreate2(file, "format_version", H5T_STD_I64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT),
                 H5Aclose, "cannot create attribute format_version");
  check(H5Awrite(version.get(), H5T_NATIVE_INT64, &checkpoint_format_version),
        "cannot write attribute format_version");
}

/// The file access properties: MPI-IO over every rank when collective.
Handle access(const Part& part) {
  Handle fapl = file_access();
#ifdef MPM_COLLECTIVE_CHECKPOINTS
  if (part.collective)
    check(H5Pset_fapl_mpio(fapl.get(), MPI_COMM_WORLD, MPI_INFO_NULL), "cannot open the file on every rank");
#else
  (void)part;
#endif
  return fapl;
}

/// Write every entry of `data` into a new HDF5 file at `path` and flush it; the file is closed on return.
void write_hdf5(const fs::path& path, const CheckpointData& data, const Part& part) {
  Handle fapl = access(part);
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create file creation properties");
  check(H5Pset_userblock(fcpl.get(), seal::userblock_bytes), "cannot reserve the seal's userblock");
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose,
              "cannot create " + path.string());
  write_root_attributes(file.get());
  {
    Handle group = create_group(file.get(), reals_group);
    for (const auto& [name, values] : data.reals)
      write_array(group.get(), reals_group, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values, data, part);
  }
  {
    Handle group = create_group(file.get(), integers_group);
    for (const auto& [name, values] : data.integers)
      write_array(group.get(), integers_group, name, H5T_STD_I64LE, H5T_NATIVE_INT64, values, data, part);
  }
  {
    Handle group = create_group(file.get(), real_scalars_group);
    for (const auto& [name, value] : data.real_scalars)
      write_single(group.get(), std::string(real_scalars_group) + "/" + name, name, H5T_IEEE_F64LE,
                   H5T_NATIVE_DOUBLE, H5S_SCALAR, &value, part);
  }
  {
    Handle group = create_group(file.get(), integer_scalars_group);
    for (const auto& [name, value] : data.integer_scalars)
      write_single(group.get(), std::string(integer_scalars_group) + "/" + name, name, H5T_STD_I64LE,
                   H5T_NATIVE_INT64, H5S_SCALAR, &value, part);
  }
  {
    Handle group = create_group(file.get(), texts_group);
    for (const auto& [name, text] : data.texts) {  // the exact bytes; an empty text gets a null dataspace
      Handle type = string_type(text.size());
      write_single(group.get(), std::string(texts_group) + "/" + name, name, type.get(), type.get(),
                   text.empty() ? H5S_NULL : H5S_SCALAR, text.data(), part);
    }
  }
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "cannot flush " + path.string());
}

/// fsync(2) a file or directory by path. Directories on some file systems refuse fsync with EINVAL; that is
/// not an error (there is nothing more we could do).
void fsync_path(const fs::path& path, bool directory) {
  const int fd =
      ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY | O_CLOEXEC) : (O_RDONLY | O_CLOEXEC));
  if (fd < 0) throw Failure("cannot open " + path.string() + ": " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && !(directory && err == EINVAL))
    throw Failure("cannot fsync " + path.string() + ": " + std::strerror(err));
}

/// Seal the written temporary file, make it durable and rename it over `file`.
void seal_and_rename(const fs::path& tmp, const fs::path& file) {
  const fs::path parent = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  if (!seal::write(tmp)) throw Failure("cannot seal " + tmp.string() + ": " + std::strerror(errno));
  fsync_path(tmp, false);
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) throw Failure("cannot rename " + tmp.string() + " to it: " + ec.message());
  fsync_path(parent, true);
}

}  // namespace

fs::path checkpoint_temp_prefix(const fs::path& file) {
  fs::path prefix = file;
  prefix += ".tmp-";
  return prefix;
}

bool collective_checkpoints() {
#ifdef MPM_COLLECTIVE_CHECKPOINTS
  return true;
#else
  return false;
#endif
}

void write_checkpoint(const fs::path& file, const CheckpointData& data) {
  write_checkpoint(file, data, one_process());
}

void write_checkpoint(const fs::path& file, const CheckpointData& data, const Communicator& comm) {
  static std::atomic<unsigned long> counter{0};
  Part part;
  part.root = comm.rank() == 0;
  part.collective = comm.size() > 1;
  if (part.collective && !collective_checkpoints())
    throw InputError("checkpoint " + file.string() +
                     ": this mpm was built without parallel HDF5 "
                     "(libhdf5-openmpi-dev), which a checkpoint of a run divided between ranks needs");
  std::string failure;
  try {
    check_names(data);
    part.count = own_rows(data);
  } catch (const Failure& e) {
    failure = e.what();
  }
  failure = first_failure(comm, failure);
  if (!failure.empty()) throw InputError("checkpoint " + file.string() + ": " + failure);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(comm.size()), 0);
  counts[static_cast<std::size_t>(comm.rank())] = part.count;
  comm.sum(counts);
  for (int r = 0; r < comm.size(); ++r) {
    if (r < comm.rank()) part.first += counts[static_cast<std::size_t>(r)];
    part.total += counts[static_cast<std::size_t>(r)];
  }

  fs::path tmp = checkpoint_temp_prefix(file);
  tmp += broadcast_text(comm, std::to_string(::getpid()) + "-" + std::to_string(counter++), 0);
  const SilenceErrors silence;
  try {
    write_hdf5(tmp, data, part);
  } catch (const Failure& e) {
    failure = e.what();
  }
  failure = first_failure(comm, failure);
  if (failure.empty() && part.root) try {
      seal_and_rename(tmp, file);
    } catch (const Failure& e) {
      failure = e.what();
    }
  failure = first_failure(comm, failure);
  if (failure.empty()) return;
  if (part.root) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
  }
  throw OutputError("checkpoint " + file.string() + ": " + failure);
}

}  // namespace mpm::io

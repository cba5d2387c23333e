/// The HDF5 checkpoint file: layout in include/mpm/io/checkpoint.hpp. Written to a temporary file in the same
/// directory, flushed and fsynced, then renamed over the target (rename(2) is atomic within a file system) and
/// the directory fsynced, so a reader sees either the old checkpoint or the new one.
#include "mpm/io/checkpoint.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "checkpoint_seal.hpp"
#include "mpm/core/errors.hpp"

namespace mpm::io {

namespace fs = std::filesystem;

namespace {

constexpr const char* reals_group = "/reals";
constexpr const char* integers_group = "/integers";
constexpr const char* real_scalars_group = "/real_scalars";
constexpr const char* integer_scalars_group = "/integer_scalars";
constexpr const char* texts_group = "/texts";

/// A failure inside this file; the public functions prefix it with "checkpoint FILE: ".
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void check(herr_t status, const std::string& what) {
  if (status < 0) throw Failure(what);
}

/// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer close, const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw Failure(what);
  }
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle& operator=(Handle&&) = delete;
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  Closer close_;
};

/// Turns off HDF5's printing of its error stack for this scope (we report our own errors), then restores it.
class SilenceHdf5Errors {
 public:
  SilenceHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  SilenceHdf5Errors(const SilenceHdf5Errors&) = delete;
  SilenceHdf5Errors& operator=(const SilenceHdf5Errors&) = delete;
  ~SilenceHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// File access properties: close every object with the file, and no flock (the temporary file is private to
/// its writer, a finished checkpoint is only read, and some file systems do not support locks).
Handle file_access() {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create file access properties");
  check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "cannot set file close degree");
#if H5_VERSION_GE(1, 10, 7)
  check(H5Pset_file_locking(fapl.get(), false, true), "cannot disable file locking");
#endif
  return fapl;
}

/// A fixed-length string type holding exactly `size` bytes (at least 1), padded with NULs.
Handle string_type(std::size_t size) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "cannot create string type");
  check(H5Tset_size(type.get(), size > 0 ? size : 1), "cannot size string type");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "cannot pad string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "cannot set string character set");
  return type;
}

// ---- writing --------------------------------------------------------------------------------------------

void check_name(const std::string& kind, const std::string& name) {
  if (name.empty() || name == "." || name.find('/') != std::string::npos)
    throw Failure("invalid " + kind + " name '" + name + "' (must be non-empty, not '.', without '/')");
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

/// A 1-D dataset of n values; zero-length arrays are a dataspace of extent 0 and nothing written.
void write_array(hid_t group, const std::string& path, const std::string& name, hid_t file_type,
                 hid_t mem_type, const void* values, std::size_t n) {
  const hsize_t dims[1] = {n};
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "cannot create dataspace for " + path);
  Handle set = create_dataset(group, path, name, file_type, space.get());
  if (n > 0) check(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "cannot write " + path);
}

void write_scalar(hid_t group, const std::string& path, const std::string& name, hid_t file_type,
                  hid_t mem_type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "cannot create dataspace for " + path);
  Handle set = create_dataset(group, path, name, file_type, space.get());
  check(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, value), "cannot write " + path);
}

/// The exact bytes of `text` as one fixed-length string; an empty text gets a null dataspace.
void write_text(hid_t group, const std::string& path, const std::string& name, const std::string& text) {
  Handle type = string_type(text.size());
  Handle space(H5Screate(text.empty() ? H5S_NULL : H5S_SCALAR), H5Sclose, "cannot create dataspace for " + path);
  Handle set = create_dataset(group, path, name, type.get(), space.get());
  if (!text.empty())
    check(H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()), "cannot write " + path);
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

/// Write every entry of `data` into a new HDF5 file at `path` and flush it; the file is closed on return.
void write_hdf5(const fs::path& path, const CheckpointData& data) {
  Handle fapl = file_access();
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create file creation properties");
  check(H5Pset_userblock(fcpl.get(), seal::userblock_bytes), "cannot reserve the seal's userblock");
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose,
              "cannot create " + path.string());
  write_root_attributes(file.get());
  {
    Handle group = create_group(file.get(), reals_group);
    for (const auto& [name, values] : data.reals)
      write_array(group.get(), std::string(reals_group) + "/" + name, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                  values.data(), values.size());
  }
  {
    Handle group = create_group(file.get(), integers_group);
    for (const auto& [name, values] : data.integers)
      write_array(group.get(), std::string(integers_group) + "/" + name, name, H5T_STD_I64LE, H5T_NATIVE_INT64,
                  values.data(), values.size());
  }
  {
    Handle group = create_group(file.get(), real_scalars_group);
    for (const auto& [name, value] : data.real_scalars)
      write_scalar(group.get(), std::string(real_scalars_group) + "/" + name, name, H5T_IEEE_F64LE,
                   H5T_NATIVE_DOUBLE, &value);
  }
  {
    Handle group = create_group(file.get(), integer_scalars_group);
    for (const auto& [name, value] : data.integer_scalars)
      write_scalar(group.get(), std::string(integer_scalars_group) + "/" + name, name, H5T_STD_I64LE,
                   H5T_NATIVE_INT64, &value);
  }
  {
    Handle group = create_group(file.get(), texts_group);
    for (const auto& [name, text] : data.texts)
      write_text(group.get(), std::string(texts_group) + "/" + name, name, text);
  }
  check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "cannot flush " + path.string());
}

/// fsync(2) a file or directory by path. Directories on some file systems refuse fsync with EINVAL; that is
/// not an error (there is nothing more we could do).
void fsync_path(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY | O_CLOEXEC) : (O_RDONLY | O_CLOEXEC));
  if (fd < 0) throw Failure("cannot open " + path.string() + ": " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && !(directory && err == EINVAL))
    throw Failure("cannot fsync " + path.string() + ": " + std::strerror(err));
}

// ---- reading --------------------------------------------------------------------------------------------

/// The names of the links in `group`, in name order.
std::vector<std::string> member_names(hid_t group, const std::string& path) {
  H5G_info_t info;
  check(H5Gget_info(group, &info), "cannot list " + path);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) throw Failure("cannot list " + path);
    std::vector<char> buffer(static_cast<std::size_t>(len) + 1);
    if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, buffer.data(), buffer.size(),
                           H5P_DEFAULT) < 0)
      throw Failure("cannot list " + path);
    names.emplace_back(buffer.data(), static_cast<std::size_t>(len));
  }
  return names;
}

/// Calls fn(name, path, dataset) for every member of the group at `group_path`; a missing group holds nothing.
template <class Fn>
void for_each_dataset(hid_t file, const char* group_path, Fn&& fn) {
  const htri_t exists = H5Lexists(file, group_path, H5P_DEFAULT);
  if (exists < 0) throw Failure(std::string("cannot look up ") + group_path);
  if (exists == 0) return;
  Handle group(H5Gopen2(file, group_path, H5P_DEFAULT), H5Gclose, std::string(group_path) + " is not a group");
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

template <class T>
std::vector<T> read_array(hid_t set, const std::string& path, H5T_class_t cls, hid_t mem_type, const char* what) {
  expect_class(set, cls, path, what);
  Handle space(H5Dget_space(set), H5Sclose, "cannot get the dataspace of " + path);
  if (H5Sget_simple_extent_type(space.get()) != H5S_SIMPLE || H5Sget_simple_extent_ndims(space.get()) != 1)
    throw Failure(path + " is not a 1-D array");
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw Failure("cannot get the size of " + path);
  std::vector<T> values(static_cast<std::size_t>(n));
  if (n > 0) check(H5Dread(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "cannot read " + path);
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
  Handle version(H5Aopen(file, "format_version", H5P_DEFAULT), H5Aclose, "cannot open attribute format_version");
  Handle vtype(H5Aget_type(version.get()), H5Tclose, "cannot get the type of attribute format_version");
  if (H5Tget_class(vtype.get()) != H5T_INTEGER) throw Failure("'format_version' is not an integer");
  std::int64_t v = 0;
  check(H5Aread(version.get(), H5T_NATIVE_INT64, &v), "cannot read attribute format_version");
  if (v != checkpoint_format_version)
    throw Failure("format_version " + std::to_string(v) + " is not supported (this build reads " +
                  std::to_string(checkpoint_format_version) + ")");
}

CheckpointData read_hdf5(const fs::path& path) {
  Handle fapl = file_access();
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose, "cannot open as HDF5");
  check_marker(file.get());
  CheckpointData data;
  for_each_dataset(file.get(), reals_group, [&](const std::string& name, const std::string& p, hid_t set) {
    data.reals[name] = read_array<double>(set, p, H5T_FLOAT, H5T_NATIVE_DOUBLE, "reals");
  });
  for_each_dataset(file.get(), integers_group, [&](const std::string& name, const std::string& p, hid_t set) {
    data.integers[name] = read_array<std::int64_t>(set, p, H5T_INTEGER, H5T_NATIVE_INT64, "integers");
  });
  for_each_dataset(file.get(), real_scalars_group, [&](const std::string& name, const std::string& p, hid_t set) {
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

[[noreturn]] void fail(const fs::path& file, const std::string& what) {
  throw InputError("checkpoint " + file.string() + ": " + what);
}

}  // namespace

fs::path checkpoint_temp_prefix(const fs::path& file) {
  fs::path prefix = file;
  prefix += ".tmp-";
  return prefix;
}

void write_checkpoint(const fs::path& file, const CheckpointData& data) {
  static std::atomic<unsigned long> counter{0};
  fs::path tmp = checkpoint_temp_prefix(file);
  tmp += std::to_string(::getpid()) + "-" + std::to_string(counter++);
  const fs::path parent = file.parent_path().empty() ? fs::path(".") : file.parent_path();

  try {
    for (const auto& entry : data.reals) check_name("real array", entry.first);
    for (const auto& entry : data.integers) check_name("integer array", entry.first);
    for (const auto& entry : data.real_scalars) check_name("real scalar", entry.first);
    for (const auto& entry : data.integer_scalars) check_name("integer scalar", entry.first);
    for (const auto& entry : data.texts) check_name("text", entry.first);
  } catch (const Failure& e) {
    fail(file, e.what());
  }
  const SilenceHdf5Errors silence;
  try {
    write_hdf5(tmp, data);
    if (!seal::write(tmp)) throw Failure("cannot seal " + tmp.string() + ": " + std::strerror(errno));
    fsync_path(tmp, false);
    std::error_code ec;
    fs::rename(tmp, file, ec);
    if (ec) throw Failure("cannot rename " + tmp.string() + " to it: " + ec.message());
    fsync_path(parent, true);
  } catch (const Failure& e) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw OutputError("checkpoint " + file.string() + ": " + e.what());
  }
}

CheckpointData read_checkpoint(const fs::path& file) {
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (!fs::exists(status)) fail(file, "no such file");
  if (!fs::is_regular_file(status)) fail(file, "not a regular file");

  // HDF5 reads the file only if it is exactly as written: HDF5 1.10 may allocate gigabytes, leak, or print to
  // stderr at exit on a corrupt file (docs/hardening.md), so an unsealed one is not handed to it either.
  std::string why;
  switch (seal::verify(file, why)) {
    case seal::Verdict::foreign:
      fail(file, "not an HDF5 file");
    case seal::Verdict::unsealed:
      fail(file, "an HDF5 file without the checkpoint seal (written by another program, or by mpm before "
                 "checkpoints were sealed): not read");
    case seal::Verdict::corrupt:
      fail(file, "corrupt: " + why);
    case seal::Verdict::sealed:
      break;
  }
  const SilenceHdf5Errors silence;
  const htri_t is_hdf5 = H5Fis_hdf5(file.c_str());
  if (is_hdf5 < 0) fail(file, "cannot be opened");
  if (is_hdf5 == 0) fail(file, "not an HDF5 file");
  try {
    return read_hdf5(file);
  } catch (const Failure& e) {
    fail(file, e.what());
  }
}

}  // namespace mpm::io

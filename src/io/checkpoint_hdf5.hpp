#pragma once
// What the checkpoint writer and reader share (src/io/checkpoint_write.cpp, checkpoint_read.cpp): the file's
// group names, HDF5 handles that close themselves, and the error type both report through; the handles and
// the listing of a group also serve the particle files' reader (src/io/hdf5_columns.cpp).
#include <hdf5.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

// Checkpoints divided between ranks are written through MPI-IO: an MPI build with parallel HDF5.
#if defined(MPM_WITH_MPI) && defined(H5_HAVE_PARALLEL)
#define MPM_COLLECTIVE_CHECKPOINTS 1
#endif

namespace mpm::io::hdf5 {

inline constexpr const char* reals_group = "/reals";
inline constexpr const char* integers_group = "/integers";
inline constexpr const char* real_scalars_group = "/real_scalars";
inline constexpr const char* integer_scalars_group = "/integer_scalars";
inline constexpr const char* texts_group = "/texts";
/// The attribute of an array of rows: the values per row.
inline constexpr const char* row_width_attribute = "row_width";

/// A failure inside the writer or the reader; the public functions prefix it with "checkpoint FILE: ".
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline void check(herr_t status, const std::string& what) {
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
class SilenceErrors {
 public:
  SilenceErrors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  SilenceErrors(const SilenceErrors&) = delete;
  SilenceErrors& operator=(const SilenceErrors&) = delete;
  ~SilenceErrors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// File access properties: close every object with the file, and no flock (the temporary file is private to
/// its writer, a finished checkpoint is only read, and some file systems do not support locks).
inline Handle file_access() {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create file access properties");
  check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "cannot set file close degree");
#if H5_VERSION_GE(1, 10, 7)
  check(H5Pset_file_locking(fapl.get(), false, true), "cannot disable file locking");
#endif
  return fapl;
}

/// A fixed-length string type holding exactly `size` bytes (at least 1), padded with NULs.
inline Handle string_type(std::size_t size) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "cannot create string type");
  check(H5Tset_size(type.get(), size > 0 ? size : 1), "cannot size string type");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "cannot pad string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "cannot set string character set");
  return type;
}

/// The names of the links in `group`, in name order.
inline std::vector<std::string> member_names(hid_t group, const std::string& path) {
  H5G_info_t info;
  check(H5Gget_info(group, &info), "cannot list " + path);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) throw Failure("cannot list " + path);
    std::vector<char> buffer(static_cast<std::size_t>(len) + 1);
    if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, buffer.data(), buffer.size(),
                           H5P_DEFAULT) < 0)
      throw Failure("cannot list " + path);
    names.emplace_back(buffer.data(), static_cast<std::size_t>(len));
  }
  return names;
}

}  // namespace mpm::io::hdf5

#pragma once
// The seal of a checkpoint file: the file's first 512 bytes (an HDF5 userblock, which HDF5 skips) hold a text
// header with the length and the FNV-1a 64-bit hash of everything after them. The reader checks it before
// HDF5 parses the file, so a file changed or truncated after it was written is refused with one line, and
// HDF5 (which may allocate gigabytes or leak on corrupt input) only ever reads files as they were written.
//
//   mpm-checkpoint-seal 1\n
//   bytes N\n              (N: bytes after the userblock)
//   fnv1a64 HHHHHHHHHHHHHHHH\n
//   zero bytes up to offset 512
#include <cstddef>
#include <filesystem>
#include <string>

namespace mpm::io::seal {

/// The userblock size the checkpoint writer reserves.
inline constexpr std::size_t userblock_bytes = 512;

/// Write the header into the userblock of the closed HDF5 file `file`; false when it cannot (errno set).
bool write(const std::filesystem::path& file);

enum class Verdict {
  sealed,    ///< the header matches the contents
  unsealed,  ///< an HDF5 file without a seal (written by another program, or before seals)
  corrupt,   ///< a seal whose length or hash does not match, or a damaged header
  foreign,   ///< neither a seal nor an HDF5 signature at the start: not an HDF5 file
};

/// Check `file`; for `corrupt`, `why` says what does not match.
Verdict verify(const std::filesystem::path& file, std::string& why);

}  // namespace mpm::io::seal

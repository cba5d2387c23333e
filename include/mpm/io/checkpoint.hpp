#pragma once
/// A generic, crash-safe checkpoint file in HDF5: named real and integer arrays, scalars and texts, stored
/// bit-exactly. The simulation state writer and reader are built on top of it.
///
/// Layout of the file (HDF5 1.8-compatible, readable with h5dump):
///   bytes 0-511         the seal, an HDF5 userblock (src/checkpoint_seal.hpp): length and FNV-1a 64 hash of
///                       the rest of the file, checked before HDF5 reads it
///   /                   attributes "format" = "mpm-checkpoint" (string), "format_version" = 1 (int64)
///   /reals/NAME         1-D IEEE F64LE dataset (possibly of length 0); an array of rows (the particles'
///                       fields, CheckpointData::row_widths) carries the attribute "row_width" (int64): its
///                       values are rows of that many, row after row
///   /integers/NAME      1-D STD I64LE dataset (possibly of length 0), "row_width" as for /reals
///   /real_scalars/NAME  scalar IEEE F64LE dataset
///   /integer_scalars/NAME  scalar STD I64LE dataset
///   /texts/NAME         scalar fixed-length string dataset holding the exact bytes (NULLPAD, UTF-8);
///                       an empty text is a dataset with a null dataspace
/// A reader treats a missing group as holding nothing and ignores other objects at the root. Every array of
/// rows holds the same number of rows. A run divided between ranks writes one file together, each rank its
/// own rows after those of the ranks before it, and reads it on any number of ranks, each its share of the
/// rows.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mpm {
class Communicator;
}

namespace mpm::io {

/// The `format` attribute every checkpoint carries at its root.
inline constexpr const char* checkpoint_format = "mpm-checkpoint";
/// The `format_version` this code writes and reads.
inline constexpr std::int64_t checkpoint_format_version = 1;

/// The contents of a checkpoint: named arrays and scalars, bit-exact. Names must be non-empty and contain
/// no '/' (they become HDF5 link names).
struct CheckpointData {
  std::map<std::string, std::vector<double>> reals;  ///< e.g. "x" with Dim values per particle, flat
  std::map<std::string, std::vector<std::int64_t>> integers;
  std::map<std::string, double> real_scalars;           ///< e.g. "time"
  std::map<std::string, std::int64_t> integer_scalars;  ///< e.g. "steps", "dim"
  std::map<std::string, std::string> texts;             ///< e.g. "scene" (the scene file text), "version"
  /// The arrays of `reals` and `integers` that hold rows (one per particle, say), by name: the values per row
  /// (e.g. "x": Dim). Divided between ranks, these are each rank's own rows; everything else is whole.
  std::map<std::string, std::int64_t> row_widths;

  bool operator==(const CheckpointData&) const = default;  ///< value equality (note: NaN != NaN)
};

/// The prefix of the temporary files write_checkpoint() uses for FILE: "FILE.tmp-". The full temporary name
/// is "FILE.tmp-PID-N" (PID the writing process, N a per-process counter), in the same directory as FILE so
/// the final rename is atomic. Such a file exists only while a write is in progress, or was left behind by
/// a writer that crashed; it is never read and may be deleted once no writer runs.
std::filesystem::path checkpoint_temp_prefix(const std::filesystem::path& file);

/// Write atomically: write FILE.tmp-PID-N, H5Fflush + close, fsync the file, rename over FILE, fsync the
/// directory. A crash at any moment leaves either the old FILE or the new one, never a torn file.
/// Throws mpm::OutputError("checkpoint FILE: ...") naming the path when it cannot be written (the temporary
/// file is then removed and FILE left as it was), mpm::InputError for an invalid name in `data`.
void write_checkpoint(const std::filesystem::path& file, const CheckpointData& data);

/// Write one checkpoint from every rank of `comm` together (call it on every rank): each rank's rows of the
/// arrays of rows go after those of the ranks before it; everything else must be the same on every rank and
/// is written once. Atomic and sealed as above. Among several ranks this needs an MPI build with parallel
/// HDF5 (collective_checkpoints()); a failure on any rank is an OutputError on every rank.
void write_checkpoint(const std::filesystem::path& file, const CheckpointData& data,
                      const Communicator& comm);

/// Whether write_checkpoint can run among several ranks: an MPI build with parallel HDF5 (Debian's
/// libhdf5-openmpi-dev).
bool collective_checkpoints();

/// Read a checkpoint; throws mpm::InputError("checkpoint FILE: ...") naming the file and what is wrong when
/// it is missing, not HDF5, sealed but changed or truncated since it was written, lacks the format marker,
/// has another format_version, or holds an object of the wrong kind in one of its groups. HDF5's own error
/// stack printing is silenced while it runs.
CheckpointData read_checkpoint(const std::filesystem::path& file);

/// Read this rank's part of a checkpoint, on any number of ranks (call it on every rank): of the n rows in
/// the file, rank r of R gets rows [n r / R, n (r + 1) / R) of every array of rows; everything else whole.
/// Rank 0 checks the seal for all; errors as read_checkpoint, the same on every rank.
CheckpointData read_checkpoint(const std::filesystem::path& file, const Communicator& comm);

}  // namespace mpm::io

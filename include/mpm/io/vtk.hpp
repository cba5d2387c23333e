#pragma once
/// Particle output for ParaView: VTK XML PolyData files (.vtp, one vertex per particle, raw binary appended
/// data) and a ParaView collection (.pvd) that lists them by time.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mpm::io {

/// One point-data array: `components` values per point, stored point by point.
struct PointField {
  std::string name;    ///< array name shown in ParaView (e.g. "velocity", "stress", "J")
  int components = 1;  ///< values per point: 1 scalar, 3 vector, 6 symmetric tensor (xx yy zz xy yz xz)
  std::vector<double> values;  ///< components * (number of points) values, point by point
  bool integer = false;        ///< written as Int64 (the values are whole numbers of magnitude below 2^53)
  /// The components' names, which ParaView shows instead of numbers (none, or one per component).
  std::vector<std::string> component_names = {};
  /// The unit of the values ("m/s", "Pa", "1" for a dimensionless number); empty: none (an index).
  std::string unit = {};
};

/// Write a VTK XML PolyData file (.vtp) with one vertex per point. `points` holds 3 coordinates per point
/// (1-D and 2-D callers pad with zeros); each field becomes a Float64 (or, when `integer`, Int64)
/// <PointData> array with its components' names (ComponentName0, ...). The units are field data: a string
/// array `units` of one "name: unit" per field that has a unit (the points' "Points: m" first). The data are
/// raw little-endian binary in one <AppendedData encoding="raw"> block, each array preceded by its byte count
/// as a UInt64. The file is written to FILE.tmp and renamed over FILE, so readers never see a partial file.
/// Throws InputError on inconsistent sizes, OutputError when the file cannot be written (naming the path).
void write_vtp(const std::filesystem::path& file, const std::vector<double>& points,
               const std::vector<PointField>& fields);

/// Write a parallel PolyData file (.pvtp) that gathers `pieces` (.vtp paths relative to its folder), each
/// written by write_vtp with these `fields`: what ParaView opens as one data set of a run divided between
/// ranks. Written atomically; OutputError when it cannot be written.
void write_pvtp(const std::filesystem::path& file, const std::vector<PointField>& fields,
                const std::vector<std::string>& pieces);

/// A ParaView time-series collection (.pvd) that lists one dataset per output time.
class PvdSeries {
 public:
  /// An empty series that will be written to `pvd_file`; nothing is written until the first add().
  explicit PvdSeries(std::filesystem::path pvd_file);

  /// Append `dataset` (a path relative to the .pvd's folder) at `time` and rewrite the .pvd atomically (tmp
  /// file + rename). Times are written with 17 significant digits, so they read back bit for bit. Throws
  /// InputError when the time is not finite, OutputError when the file cannot be written.
  void add(double time, const std::string& dataset);

  /// Re-read a .pvd written by this class (for restarted runs), keeping the entries with time <= t_max; when
  /// entries were dropped the file is rewritten without them. Throws InputError when the file cannot be read
  /// or is not a collection in this format.
  static PvdSeries resume(std::filesystem::path pvd_file, double t_max);

  /// The (time, dataset) entries in the order they were added.
  const std::vector<std::pair<double, std::string>>& entries() const { return entries_; }

  /// The .pvd file this series writes.
  const std::filesystem::path& file() const { return file_; }

 private:
  void write() const;

  std::filesystem::path file_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace mpm::io

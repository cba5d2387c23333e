#pragma once
// The output folder of a scene run: particles.pvd and its frames, history.csv and newton.csv. Divided between
// ranks, rank 0 makes the folder and writes every file but the frames' pieces, which each rank writes for its
// own particles.
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/io/checkpoint.hpp"
#include "mpm/io/vtk.hpp"
#include "run_csv.hpp"
#include "run_newton_log.hpp"

namespace mpm {

class RunFiles {
 public:
  RunFiles(std::filesystem::path dir, const Communicator& comm) : dir_(std::move(dir)), comm_(comm) {}

  /// Make the folder. A fresh run clears an earlier run's outputs; a restart at time t (step `steps`) keeps
  /// the frames, history rows and Newton log rows up to its checkpoint and removes the frame files after
  /// them. Both remove the temporary checkpoints (checkpoint.h5.tmp-PID-N) a run killed while writing one
  /// left behind, and an earlier failed run's last state (particles_fail). Returns the frames written so far,
  /// rank 0's count on every rank (so that all write the next at one step).
  std::int64_t prepare(bool restart, Real t, std::int64_t steps, const std::string& history_header,
                       bool newton_log) {
    std::int64_t frames = 0;
    if (comm_.rank() == 0) frames = prepare_on_root(restart, t, steps, history_header, newton_log);
    std::vector<std::int64_t> agreed{frames};
    comm_.sum(agreed);  // also: the folder exists before any rank writes a piece there
    return agreed[0];
  }

  /// Frame `index` at time t: particles_NNNN.vtp, or divided between ranks one piece per rank,
  /// particles_NNNN_R.vtp, gathered by rank 0's particles_NNNN.pvtp; listed in particles.pvd.
  void frame(std::int64_t index, Real t, const std::vector<double>& points,
             const std::vector<io::PointField>& fields) {
    std::ostringstream name;
    name << "particles_" << std::setw(4) << std::setfill('0') << index;
    const std::string file = write_particles(name.str(), points, fields);
    if (comm_.rank() == 0) series_.add(t, file);
  }

  /// The last state of a failed run: particles_fail.vtp (or .pvtp with its pieces), not in particles.pvd.
  /// Returns the file's name.
  std::string failure_frame(const std::vector<double>& points, const std::vector<io::PointField>& fields) {
    return write_particles(failure_name, points, fields);
  }

  /// history.csv, open on rank 0 only.
  CsvFile& history() { return history_; }
  /// newton.csv, open with [output] newton_log = "on".
  NewtonLog& newton_log() { return newton_log_; }
  /// Flush the per-step files, so that a checkpoint written now finds every row before it after a restart.
  void flush() {
    if (history_.is_open()) history_.flush();
    if (newton_log_.is_open()) newton_log_.flush();
  }

 private:
  static constexpr const char* failure_name = "particles_fail";

  /// NAME.vtp, or divided between ranks one piece per rank, NAME_R.vtp, gathered by rank 0's NAME.pvtp.
  /// Returns the name of the file that holds the whole (NAME.vtp or NAME.pvtp).
  std::string write_particles(const std::string& name, const std::vector<double>& points,
                              const std::vector<io::PointField>& fields) {
    if (comm_.size() == 1) {
      io::write_vtp(dir_ / (name + ".vtp"), points, fields);
      return name + ".vtp";
    }
    const auto piece = [&](int r) { return name + "_" + std::to_string(r) + ".vtp"; };
    io::write_vtp(dir_ / piece(comm_.rank()), points, fields);
    comm_.min(0);  // every piece is written before the set that lists them
    if (comm_.rank() == 0) {
      std::vector<std::string> pieces;
      for (int r = 0; r < comm_.size(); ++r) pieces.push_back(piece(r));
      io::write_pvtp(dir_ / (name + ".pvtp"), fields, pieces);
    }
    return name + ".pvtp";
  }

  /// The index of a frame file's name (particles_NNNN.vtp, .pvtp or _R.vtp); -1 for other files.
  static std::int64_t frame_index(const std::filesystem::path& file) {
    const std::string name = file.filename().string(), ext = file.extension().string();
    if (name.rfind("particles_", 0) != 0 || (ext != ".vtp" && ext != ".pvtp")) return -1;
    std::int64_t index = 0;
    std::size_t at = 10;
    for (; at < name.size() && name[at] >= '0' && name[at] <= '9'; ++at)
      index = 10 * index + (name[at] - '0');
    return at > 10 ? index : -1;
  }

  std::int64_t prepare_on_root(bool restart, Real t, std::int64_t steps, const std::string& history_header,
                               bool newton_log) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec || !fs::is_directory(dir_))
      throw InputError("--out " + dir_.string() + ": cannot make the output folder" +
                       (ec ? ": " + ec.message() : " (a file of that name exists)"));
    const fs::path pvd = dir_ / "particles.pvd";
    series_ = restart && fs::exists(pvd) ? io::PvdSeries::resume(pvd, t) : io::PvdSeries(pvd);
    const auto frames = restart ? static_cast<std::int64_t>(series_.entries().size()) : 0;
    const std::string stray = io::checkpoint_temp_prefix(dir_ / "checkpoint.h5").filename().string();
    for (const fs::directory_entry& e : fs::directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      if (frame_index(e.path()) >= frames || name.rfind(stray, 0) == 0 || name.rfind(failure_name, 0) == 0 ||
          (!restart && (name == "particles.pvd" || name == "history.csv" || name == "newton.csv" ||
                        name == "summary.json")))
        fs::remove(e.path(), ec);
    }
    // After a restart, history.csv and newton.csv keep the rows up to the checkpoint's step and go on from
    // there.
    history_.open(dir_ / "history.csv", history_header, restart, steps);
    if (newton_log)
      newton_log_.open(dir_ / "newton.csv", restart, steps);
    else if (restart && fs::exists(dir_ / "newton.csv"))
      NewtonLog::trim(dir_ / "newton.csv", steps);  // an earlier run's log ends at the checkpoint
    return frames;
  }

  std::filesystem::path dir_;
  const Communicator& comm_;
  io::PvdSeries series_{""};
  CsvFile history_;
  NewtonLog newton_log_;
};

}  // namespace mpm

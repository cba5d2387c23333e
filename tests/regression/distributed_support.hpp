#pragma once
// Helpers of the tests that run `mpm` under mpirun (test_distributed_*.cpp): the launch command, and the
// frames of a run read back by particle id, whichever rank wrote them.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "support.hpp"

namespace mpm::testing {

namespace fs = std::filesystem;

inline const fs::path source_dir = fs::path(__FILE__).parent_path().parent_path().parent_path();

/// `mpirun -np ranks mpm`, as root too; under AddressSanitizer with leak checks off, as OpenMPI's own
/// allocations at start-up are reported as leaks.
inline std::string mpirun(int ranks) {
  const std::string sanitizer = MPM_SANITIZED ? "ASAN_OPTIONS=halt_on_error=1:detect_leaks=0 " : "";
  return sanitizer + "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + std::string(MPM_MPIEXEC) +
         " -np " + std::to_string(ranks) + " --oversubscribe " + MPM_BINARY;
}

/// `mpirun -np ranks mpm run SCENE --quiet ARGS`, its output in log; the exit status.
inline int run_on(int ranks, const std::string& scene, const std::string& args, const fs::path& log) {
  const std::string cmd =
      mpirun(ranks) + " run " + scene + " --quiet " + args + " >" + log.string() + " 2>&1";
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

/// The datasets particles.pvd lists, in order.
inline std::vector<std::string> frames(const fs::path& dir) {
  const std::string pvd = slurp(dir / "particles.pvd");
  std::vector<std::string> out;
  for (std::size_t at = pvd.find("file=\""); at != std::string::npos; at = pvd.find("file=\"", at + 1)) {
    at += 6;
    out.push_back(pvd.substr(at, pvd.find('"', at) - at));
  }
  return out;
}

/// The .vtp files of a frame: itself, or the pieces a .pvtp lists.
inline std::vector<fs::path> pieces(const fs::path& dir, const std::string& frame) {
  if (frame.ends_with(".vtp")) return {dir / frame};
  const std::string text = slurp(dir / frame);
  std::vector<fs::path> out;
  for (std::size_t at = text.find("Source=\""); at != std::string::npos;
       at = text.find("Source=\"", at + 1)) {
    at += 8;
    out.push_back(dir / text.substr(at, text.find('"', at) - at));
  }
  return out;
}

/// Array `name` (components per point) of a frame, all pieces, rows sorted by particle id.
inline std::vector<double> by_id(const fs::path& dir, const std::string& frame, const std::string& name,
                                 int components) {
  std::vector<double> ids, values;
  for (const fs::path& piece : pieces(dir, frame)) {
    const std::vector<double> i = vtp_array(piece, "id"), v = vtp_array(piece, name);
    ids.insert(ids.end(), i.begin(), i.end());
    values.insert(values.end(), v.begin(), v.end());
  }
  std::vector<std::size_t> order(ids.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ids[a] < ids[b]; });
  std::vector<double> out;
  for (std::size_t k : order)
    out.insert(out.end(), values.begin() + static_cast<std::ptrdiff_t>(k * components),
               values.begin() + static_cast<std::ptrdiff_t>((k + 1) * components));
  return out;
}

/// The lines mpm wrote (mpirun adds its own report of a rank's non-zero exit status).
inline int mpm_lines(const std::string& log) {
  int n = 0;
  for (std::size_t at = log.find("mpm: "); at != std::string::npos; at = log.find("mpm: ", at + 1)) ++n;
  return n;
}

inline bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](double x, double y) {
           return std::memcmp(&x, &y, sizeof x) == 0;
         });
}

}  // namespace mpm::testing

#pragma once
/// What this build of mpm is: its version, commit, compiler, flags, instruction set and the libraries it was
/// built with (`mpm --version`, summary.json's `build`).
#include <string>

namespace mpm {

struct BuildInfo {
  std::string version;     ///< the project's version (CMakeLists.txt)
  std::string commit;      ///< the commit built, "+changes" when its tracked files differed; or "unknown"
  std::string build_type;  ///< CMake's build type (Release, Debug, ...)
  std::string compiler;    ///< compiler and version
  std::string flags;       ///< the build type's compile flags and the engine's (-march, -ffp-contract=off)
  std::string isa;         ///< the widest vector instructions compiled for, and the doubles per register
  std::string hdf5;        ///< HDF5's version
  bool mpi = false;        ///< distributed runs (built with MPI)
};

/// This build's BuildInfo.
const BuildInfo& build_info();

/// BuildInfo as the lines `mpm --version` prints: "mpm VERSION (commit COMMIT)", then one "key: value" per
/// line.
std::string build_info_text();

}  // namespace mpm

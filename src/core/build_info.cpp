#include "mpm/core/build_info.hpp"

#include <H5public.h>

#include "build_commit.hpp"  // generated at every build (cmake/build_commit.cmake)
#include "mpm/core/simd.hpp"

namespace mpm {

namespace {

/// The widest vector instructions this unit was compiled for (the engine's own flags).
std::string instruction_set() {
#if defined(__AVX512F__)
  const char* isa = "AVX-512";
#elif defined(__AVX2__)
  const char* isa = "AVX2";
#elif defined(__AVX__)
  const char* isa = "AVX";
#else
  const char* isa = "SSE2";
#endif
  return std::string(isa) + ", " + std::to_string(simd::lanes) + " doubles per register";
}

}  // namespace

const BuildInfo& build_info() {
  static const BuildInfo info {
    MPM_VERSION, MPM_BUILD_COMMIT, MPM_BUILD_TYPE, MPM_COMPILER, MPM_FLAGS, instruction_set(),
        std::to_string(H5_VERS_MAJOR) + "." + std::to_string(H5_VERS_MINOR) + "." +
            std::to_string(H5_VERS_RELEASE),
#if defined(MPM_WITH_MPI)
        true
#else
        false
#endif
  };
  return info;
}

std::string build_info_text() {
  const BuildInfo& b = build_info();
  return "mpm " + b.version + " (commit " + b.commit + ")\nbuild type: " + b.build_type +
         "\ncompiler: " + b.compiler + "\nflags: " + b.flags + "\ninstruction set: " + b.isa +
         "\nMPI: " + (b.mpi ? "yes" : "no") + "\nHDF5: " + b.hdf5 + "\n";
}

}  // namespace mpm

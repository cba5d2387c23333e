// libFuzzer target: reading a checkpoint file of arbitrary bytes. A file that is not a valid checkpoint must
// end in mpm::InputError naming it; any other exception, crash, leak or hang is a finding.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/io/checkpoint.hpp"

namespace fs = std::filesystem;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fs::path file =
      fs::temp_directory_path() / ("mpm_fuzz_checkpoint_" + std::to_string(::getpid()) + ".h5");
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    (void)mpm::io::read_checkpoint(file);
  } catch (const mpm::InputError&) {
  }
  return 0;
}

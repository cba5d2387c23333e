#include "mpm/io/files.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "mpm/core/errors.hpp"

namespace mpm::io {

void write_file_atomically(const std::filesystem::path& file, std::string_view content) {
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  std::error_code ignored;
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (out) out.write(content.data(), static_cast<std::streamsize>(content.size()));
    if (out) out.close();
    if (!out) {
      const std::string reason = errno ? std::strerror(errno) : "write failed";
      std::filesystem::remove(tmp, ignored);
      throw OutputError("cannot write " + file.string() + " (writing " + tmp.string() + ": " + reason + ")");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ignored);
    throw OutputError("cannot write " + file.string() + ": " + ec.message());
  }
}

}  // namespace mpm::io

#include "checkpoint_seal.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

namespace mpm::io::seal {

namespace {
namespace fs = std::filesystem;

constexpr char magic[] = "mpm-checkpoint-seal 1\n";
constexpr unsigned char hdf5_signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// FNV-1a 64 of the bytes of `in` from its current position to the end; `count` receives their number.
std::uint64_t hash_rest(std::istream& in, std::uint64_t& count) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  std::vector<char> buffer(1 << 20);
  count = 0;
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize got = in.gcount();
    for (std::streamsize i = 0; i < got; ++i) {
      h ^= static_cast<unsigned char>(buffer[static_cast<std::size_t>(i)]);
      h *= 0x100000001b3ull;
    }
    count += static_cast<std::uint64_t>(got);
  }
  return h;
}
}  // namespace

bool write(const fs::path& file) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  if (!f) return false;
  f.seekg(static_cast<std::streamoff>(userblock_bytes));
  std::uint64_t count = 0;
  const std::uint64_t h = hash_rest(f, count);
  char header[userblock_bytes] = {};
  std::snprintf(header, sizeof header, "%sbytes %" PRIu64 "\nfnv1a64 %016" PRIx64 "\n", magic, count, h);
  f.clear();
  f.seekp(0);
  f.write(header, sizeof header);
  f.flush();
  return static_cast<bool>(f);
}

Verdict verify(const fs::path& file, std::string& why) {
  std::ifstream f(file, std::ios::binary);
  char header[userblock_bytes] = {};
  f.read(header, sizeof header);
  const auto got = static_cast<std::size_t>(f.gcount());
  if (got >= sizeof hdf5_signature && std::memcmp(header, hdf5_signature, sizeof hdf5_signature) == 0)
    return Verdict::unsealed;
  const std::size_t magic_length = sizeof magic - 1;
  if (got < magic_length || std::memcmp(header, magic, magic_length) != 0) return Verdict::foreign;
  if (got < sizeof header) {
    why = "truncated inside its header";
    return Verdict::corrupt;
  }
  std::uint64_t bytes = 0, hash = 0;
  header[sizeof header - 1] = '\0';
  if (std::sscanf(header + magic_length, "bytes %" SCNu64 "\nfnv1a64 %" SCNx64, &bytes, &hash) != 2) {
    why = "its seal header is damaged";
    return Verdict::corrupt;
  }
  std::uint64_t count = 0;
  const std::uint64_t h = hash_rest(f, count);
  if (count != bytes) {
    why = "it holds " + std::to_string(count) + " bytes after its header where " + std::to_string(bytes) +
          " were written (truncated or extended)";
    return Verdict::corrupt;
  }
  if (h != hash) {
    why =
        "its contents do not match the checksum written with them (the file was changed after it was "
        "written)";
    return Verdict::corrupt;
  }
  return Verdict::sealed;
}

}  // namespace mpm::io::seal

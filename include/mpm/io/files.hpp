#pragma once
/// Writing output files so that a reader never sees a torn one.
#include <filesystem>
#include <string_view>

namespace mpm::io {

/// Write `content` to FILE.tmp, then rename it over FILE, so a reader sees either the old or the new file.
/// Throws mpm::OutputError naming FILE when it cannot be written (disk full, file-size limit, folder gone);
/// the temporary file is then removed and FILE left as it was.
void write_file_atomically(const std::filesystem::path& file, std::string_view content);

}  // namespace mpm::io

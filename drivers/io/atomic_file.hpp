#pragma once

#include <filesystem>
#include <string_view>

namespace strata::io {

/// Writes `data` to `path` so that readers see the old file or the whole new one, never a part: a
/// temporary file next to it, then a rename. Without fsync: used for recordings, where a stream of files
/// must not stall on the disk; a crash loses the newest files, not the consistency of the older ones.
/// Throws std::runtime_error naming the file and the system's reason.
void write_file_atomically(const std::filesystem::path& path, std::string_view data);

}  // namespace strata::io

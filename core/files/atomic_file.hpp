#pragma once

#include <filesystem>
#include <stdexcept>
#include <string_view>

namespace strata {

/// How far a write must have gone before write_file_atomically() returns.
enum class Durability {
  /// The file and the rename are on disk (fsync of the file and its directory): a saved map survives a
  /// power cut as the old or the new file.
  kOnDisk,
  /// Readers see the old file or the whole new one, but a crash may lose the newest files: a recording's
  /// stream of scans must not stall on the disk.
  kOrdered,
};

/// Writing a file failed; what() names the file and the system's reason.
struct FileWriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Writes `data` to `path` so that readers see the old file or the whole new one, never a part: a temporary
/// file next to it (temporary_path_for), then a rename over `path`. On failure the temporary is removed,
/// `path` is as it was, and FileWriteError is thrown (a full disk: "File too large", "No space left"). An
/// existing `path` that is a device, a FIFO or a socket is refused ("not a regular file"), not replaced.
void write_file_atomically(const std::filesystem::path& path, std::string_view data, Durability durability);

}  // namespace strata

#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

namespace strata {

/// The temporary file an atomic save writes before renaming it over `target`: `<target>.tmp.<pid>`, next
/// to the target (the rename must not cross file systems), named by the writing process.
[[nodiscard]] std::filesystem::path temporary_path_for(const std::filesystem::path& target);

/// The process that wrote `file_name` if it is named like a save's temporary (`<name>.tmp.<digits>`, with
/// a non-empty name), else nullopt.
[[nodiscard]] std::optional<pid_t> temporary_file_owner(std::string_view file_name);

/// Removes the temporaries in `directory` (not below it) that a killed save left behind: regular files named
/// like temporary_path_for's whose process no longer exists. Nothing else is touched: other files, the
/// temporaries of a process still running (another server saving now), directories. Returns the removed
/// paths; a file that cannot be removed is skipped.
std::vector<std::filesystem::path> remove_stale_temporaries(const std::filesystem::path& directory);

}  // namespace strata

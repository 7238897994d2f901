#include "core/files/temporary_files.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <string>
#include <system_error>

namespace strata {
namespace {

constexpr std::string_view kMarker = ".tmp.";

bool process_exists(pid_t pid) {
  // Signal 0 checks without signalling; EPERM means it exists but belongs to another user.
  return ::kill(pid, 0) == 0 || errno == EPERM;
}

}  // namespace

std::filesystem::path temporary_path_for(const std::filesystem::path& target) {
  return target.string() + std::string(kMarker) + std::to_string(::getpid());
}

std::optional<pid_t> temporary_file_owner(std::string_view file_name) {
  const std::size_t marker = file_name.rfind(kMarker);
  if (marker == std::string_view::npos || marker == 0)
    return std::nullopt;
  const std::string_view digits = file_name.substr(marker + kMarker.size());
  pid_t pid = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || pid <= 0)
    return std::nullopt;  // also "+1", "-1", " 1", "1a", overflow
  return pid;
}

std::vector<std::filesystem::path> remove_stale_temporaries(const std::filesystem::path& directory) {
  std::vector<std::filesystem::path> removed;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const auto owner = temporary_file_owner(entry.path().filename().string());
    // symlink_status: a link named like a temporary is not ours, whatever it points to.
    if (!owner || !std::filesystem::is_regular_file(entry.symlink_status(error)) || process_exists(*owner))
      continue;
    if (std::filesystem::remove(entry.path(), error))
      removed.push_back(entry.path());
  }
  return removed;
}

}  // namespace strata

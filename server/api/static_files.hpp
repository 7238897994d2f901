#pragma once

#include <filesystem>
#include <optional>
#include <string_view>

namespace strata::api {

/// Maps a request path ("/", "/assets/index-abc.js") to a file below `root`, or nothing when the path
/// is not a plain relative path (parent segments, backslashes, NUL, encoded characters) or the file
/// does not exist. "/" and directories map to their index.html.
[[nodiscard]] std::optional<std::filesystem::path> resolve_static_path(const std::filesystem::path& root,
                                                                       std::string_view request_path);

/// Content-Type for a file, by extension; application/octet-stream when unknown.
[[nodiscard]] std::string_view mime_type(const std::filesystem::path& file);

}  // namespace strata::api

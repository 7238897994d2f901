#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace strata::pipeline {

/// The whole file at `path`, or none when it cannot be opened or read.
[[nodiscard]] std::optional<std::string> read_file_bytes(const std::filesystem::path& path);

}  // namespace strata::pipeline

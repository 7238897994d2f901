#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/sim/world/world.hpp"

namespace strata::sim {

/// Reads a world file (JSON; the format is described in drivers/sim/worlds/README.md). Throws
/// std::runtime_error naming the file and the offending entry when the file is unreadable or invalid.
[[nodiscard]] WorldDescription load_world_file(const std::filesystem::path& path);
/// The same from text; `source` names it in error messages.
[[nodiscard]] WorldDescription parse_world(std::string_view text, std::string_view source);

/// The worlds built into the binary: "campus" (the default) and "yard" (small, for fast tests).
[[nodiscard]] std::vector<std::string> builtin_world_names();
/// The text of a built-in world file; throws std::invalid_argument for an unknown name.
[[nodiscard]] std::string_view builtin_world_text(std::string_view name);
[[nodiscard]] WorldDescription builtin_world(std::string_view name);

}  // namespace strata::sim

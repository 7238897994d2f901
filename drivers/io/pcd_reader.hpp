#pragma once

#include <filesystem>
#include <istream>

#include "drivers/io/loaded_cloud.hpp"

namespace strata::io {

/// Reads the x, y, z fields of a PCL .pcd file (v0.5-0.7): DATA ascii, binary or binary_compressed (LZF,
/// fields stored one after another), and a "time" field where there is one (LoadedCloud::times). Other
/// fields are skipped. Throws PointFileError.
[[nodiscard]] LoadedCloud read_pcd(const std::filesystem::path& path);
/// The same from a stream (opened binary); `source` names it in error messages.
[[nodiscard]] LoadedCloud read_pcd(std::istream& in, const std::filesystem::path& source);

}  // namespace strata::io

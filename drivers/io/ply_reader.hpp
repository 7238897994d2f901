#pragma once

#include <filesystem>
#include <istream>

#include "drivers/io/loaded_cloud.hpp"

namespace strata::io {

/// Reads the x, y, z properties of a PLY file's vertex element: format ascii, binary_little_endian or
/// binary_big_endian, any numeric property types; other properties and elements (faces) are skipped.
/// Throws PointFileError.
[[nodiscard]] LoadedCloud read_ply(const std::filesystem::path& path);
/// The same from a stream (opened binary); `source` names it in error messages.
[[nodiscard]] LoadedCloud read_ply(std::istream& in, const std::filesystem::path& source);

}  // namespace strata::io

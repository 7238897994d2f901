#pragma once

#include <filesystem>
#include <istream>

#include "drivers/io/loaded_cloud.hpp"

namespace strata::io {

/// Reads a text table of points, comma- or whitespace-separated (.csv, .xyz, .txt). With a header line
/// (e.g. "x,y,z,nx,ny,nz") the columns named x, y and z are used; without one, the first three columns.
/// Lines starting with '#' are comments. Throws PointFileError.
[[nodiscard]] LoadedCloud read_xyz(const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] LoadedCloud read_xyz(std::istream& in, const std::filesystem::path& source);

}  // namespace strata::io

#pragma once

#include <filesystem>

#include "drivers/io/loaded_cloud.hpp"

namespace strata::io {

/// Reads a point cloud, choosing the reader by extension: .pcd, .ply, .3d (3DTK, converted to metres and
/// Strata's frame), .csv / .xyz / .txt. Throws PointFileError, also for an unknown extension.
[[nodiscard]] LoadedCloud read_point_cloud(const std::filesystem::path& path);

}  // namespace strata::io

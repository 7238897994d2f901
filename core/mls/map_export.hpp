#pragma once

#include <filesystem>
#include <stdexcept>

#include "core/mls/level_grid.hpp"
#include "core/mls/mls_map.hpp"

namespace strata {

struct MapExportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Writes `grid` in the ROS map_server format: `yaml_path` and, next to it with the same stem, a binary
/// PGM (free 254, occupied 0, unknown 205; first image row = highest y). Returns the PGM's path.
std::filesystem::path write_ros_map(const LevelGrid& grid, const std::filesystem::path& yaml_path);

/// Writes the MLS map as an ASCII PLY point cloud: one vertex per patch at its cell centre and top, with
/// its depth (0 = horizontal), the standard deviation of its height and whether it is vertical, coloured
/// grey (horizontal) or red (vertical).
void write_mls_ply(const MlsMap& map, const std::filesystem::path& path);

}  // namespace strata

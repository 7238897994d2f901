#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "core/mls/level_grid.hpp"
#include "core/mls/mls_map.hpp"

namespace strata {

struct MapExportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Calls `visit(cell, patch)` for every patch of `map`, tile by tile, each cell's patches lowest first:
/// what the exports (PLY, MCAP's point cloud) write.
template <typename Visit>
void for_each_patch(const MlsMap& map, Visit&& visit) {
  for (const TileIndex& tile_index : map.tile_indices()) {
    const MlsTile& tile = *map.find_tile(tile_index);
    for (int local = 0; local < kMlsTileCells; ++local) {
      const CellIndex cell{tile_index.x * kMlsTileSize + local % kMlsTileSize,
                           tile_index.y * kMlsTileSize + local / kMlsTileSize};
      tile.for_each_patch(local, [&](const MlsPatch& patch) { visit(cell, patch); });
    }
  }
}

/// `grid` as the image of a ROS map_server map: a binary PGM (free 254, occupied 0, unknown 205; first image
/// row = highest y).
[[nodiscard]] std::string ros_map_pgm(const LevelGrid& grid);
/// The ROS map_server YAML that describes `grid` and names `image` (the PGM's file name) as its image.
[[nodiscard]] std::string ros_map_yaml(const LevelGrid& grid, const std::string& image);

/// The MLS map as an ASCII PLY point cloud: one vertex per patch at its cell centre and top, with its depth
/// (0 = horizontal), the standard deviation of its height and whether it is vertical, coloured grey
/// (horizontal) or red (vertical).
[[nodiscard]] std::string mls_ply(const MlsMap& map);

/// Writes ros_map_yaml to `yaml_path` and ros_map_pgm next to it with the same stem, each atomically.
/// Returns the PGM's path. Throws MapExportError naming the file that could not be written.
std::filesystem::path write_ros_map(const LevelGrid& grid, const std::filesystem::path& yaml_path);

/// Writes mls_ply to `path` atomically; throws MapExportError when it cannot.
void write_mls_ply(const MlsMap& map, const std::filesystem::path& path);

}  // namespace strata

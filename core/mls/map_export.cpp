#include "core/mls/map_export.hpp"

#include <cmath>
#include <fstream>

namespace strata {

std::filesystem::path write_ros_map(const LevelGrid& grid, const std::filesystem::path& yaml_path) {
  std::filesystem::path pgm_path = yaml_path;
  pgm_path.replace_extension(".pgm");
  {
    std::ofstream pgm(pgm_path, std::ios::binary);
    if (!pgm)
      throw MapExportError("cannot write " + pgm_path.string());
    pgm << "P5\n# strata drivable map\n" << grid.width << ' ' << grid.height << "\n255\n";
    std::string row_bytes(static_cast<std::size_t>(grid.width), '\0');
    for (int row = grid.height - 1; row >= 0; --row) {  // image top = highest y
      for (int col = 0; col < grid.width; ++col) {
        const Occupancy o = grid.at(col, row);
        row_bytes[static_cast<std::size_t>(col)] = static_cast<char>(o == Occupancy::free       ? 254
                                                                     : o == Occupancy::occupied ? 0
                                                                                                : 205);
      }
      pgm.write(row_bytes.data(), static_cast<std::streamsize>(row_bytes.size()));
    }
    if (!pgm)
      throw MapExportError("failed writing " + pgm_path.string());
  }
  std::ofstream yaml(yaml_path);
  if (!yaml)
    throw MapExportError("cannot write " + yaml_path.string());
  yaml.precision(10);
  yaml << "image: " << pgm_path.filename().string() << "\n"
       << "mode: trinary\n"
       << "resolution: " << grid.resolution << "\n"
       << "origin: [" << grid.origin.x() << ", " << grid.origin.y() << ", 0.0]\n"
       << "negate: 0\n"
       << "occupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n";
  if (!yaml)
    throw MapExportError("failed writing " + yaml_path.string());
  return pgm_path;
}

void write_mls_ply(const MlsMap& map, const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out)
    throw MapExportError("cannot write " + path.string());
  out << "ply\nformat ascii 1.0\ncomment strata MLS map, one vertex per patch (cell centre, patch top)\n"
      << "element vertex " << map.patch_count() << "\n"
      << "property float x\nproperty float y\nproperty float z\nproperty float depth\n"
      << "property float sigma\nproperty uchar vertical\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  out.precision(7);
  for (const TileIndex& tile_index : map.tile_indices()) {
    const MlsTile& tile = *map.find_tile(tile_index);
    for (int local = 0; local < kMlsTileCells; ++local) {
      const CellIndex cell{tile_index.x * kMlsTileSize + local % kMlsTileSize,
                           tile_index.y * kMlsTileSize + local / kMlsTileSize};
      const Eigen::Vector2d centre = map.cell_center(cell);
      tile.for_each_patch(local, [&](const MlsPatch& patch) {
        const bool vertical = patch.vertical();
        out << centre.x() << ' ' << centre.y() << ' ' << patch.mean << ' ' << patch.depth << ' '
            << std::sqrt(patch.variance) << ' ' << (vertical ? 1 : 0)
            << (vertical ? " 220 60 40\n" : " 170 170 170\n");
      });
    }
  }
  if (!out)
    throw MapExportError("failed writing " + path.string());
}

}  // namespace strata

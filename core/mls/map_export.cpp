#include "core/mls/map_export.hpp"

#include <cmath>
#include <sstream>

#include "core/files/atomic_file.hpp"

namespace strata {
namespace {

void write_export(const std::filesystem::path& path, const std::string& data) {
  try {
    write_file_atomically(path, data, Durability::kOrdered);
  } catch (const FileWriteError& error) {
    throw MapExportError(error.what());
  }
}

}  // namespace

std::string ros_map_pgm(const LevelGrid& grid) {
  std::string pgm = "P5\n# strata drivable map\n" + std::to_string(grid.width) + ' ' +
                    std::to_string(grid.height) + "\n255\n";
  pgm.reserve(pgm.size() + static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height));
  for (int row = grid.height - 1; row >= 0; --row) {  // image top = highest y
    for (int col = 0; col < grid.width; ++col) {
      const Occupancy o = grid.at(col, row);
      pgm.push_back(static_cast<char>(o == Occupancy::free ? 254 : o == Occupancy::occupied ? 0 : 205));
    }
  }
  return pgm;
}

std::string ros_map_yaml(const LevelGrid& grid, const std::string& image) {
  std::ostringstream yaml;
  yaml.precision(10);
  yaml << "image: " << image << "\n"
       << "mode: trinary\n"
       << "resolution: " << grid.resolution << "\n"
       << "origin: [" << grid.origin.x() << ", " << grid.origin.y() << ", 0.0]\n"
       << "negate: 0\n"
       << "occupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n";
  return yaml.str();
}

std::string mls_ply(const MlsMap& map) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment strata MLS map, one vertex per patch (cell centre, patch top)\n"
      << "element vertex " << map.patch_count() << "\n"
      << "property float x\nproperty float y\nproperty float z\nproperty float depth\n"
      << "property float sigma\nproperty uchar vertical\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  out.precision(7);
  for_each_patch(map, [&](const CellIndex& cell, const MlsPatch& patch) {
    const Eigen::Vector2d centre = map.cell_center(cell);
    const bool vertical = patch.vertical();
    out << centre.x() << ' ' << centre.y() << ' ' << patch.mean << ' ' << patch.depth << ' '
        << std::sqrt(patch.variance) << ' ' << (vertical ? 1 : 0)
        << (vertical ? " 220 60 40\n" : " 170 170 170\n");
  });
  return out.str();
}

std::filesystem::path write_ros_map(const LevelGrid& grid, const std::filesystem::path& yaml_path) {
  std::filesystem::path pgm_path = yaml_path;
  pgm_path.replace_extension(".pgm");
  write_export(pgm_path, ros_map_pgm(grid));  // the image first: the YAML never names a missing one
  write_export(yaml_path, ros_map_yaml(grid, pgm_path.filename().string()));
  return pgm_path;
}

void write_mls_ply(const MlsMap& map, const std::filesystem::path& path) {
  write_export(path, mls_ply(map));
}

}  // namespace strata

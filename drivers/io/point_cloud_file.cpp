#include "drivers/io/point_cloud_file.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "drivers/io/pcd_reader.hpp"
#include "drivers/io/ply_reader.hpp"
#include "drivers/io/point_file_error.hpp"
#include "drivers/io/threedtk_reader.hpp"
#include "drivers/io/xyz_reader.hpp"

namespace strata::io {

LoadedCloud read_point_cloud(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".pcd")
    return read_pcd(path);
  if (extension == ".ply")
    return read_ply(path);
  if (extension == ".3d")
    return read_3dtk_scan(path);
  if (extension == ".csv" || extension == ".xyz" || extension == ".txt")
    return read_xyz(path);
  throw PointFileError(
      path, "unknown point cloud format '" + extension + "' (known: .pcd, .ply, .3d, .csv, .xyz, .txt)");
}

}  // namespace strata::io

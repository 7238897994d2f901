#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <istream>
#include <string>

#include "core/planning/occupancy_grid.hpp"

namespace strata::io {

/// The keys of a ROS map_server / Nav2 map YAML file (wiki.ros.org/map_server, "YAML format").
struct MapServerMetadata {
  std::filesystem::path image;                       ///< resolved against the YAML file's directory
  double resolution = 0.0;                           ///< metres per pixel
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< x, y (metres) of the lower-left pixel, yaw
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  std::string mode = "trinary";  ///< trinary, scale or raw
};

/// Reads the YAML file. Required: image, resolution, origin; negate, occupied_thresh, free_thresh and mode
/// default to map_server's usual values. Throws MapFileError.
[[nodiscard]] MapServerMetadata read_map_server_yaml(const std::filesystem::path& yaml_path);
/// The same from a stream; `yaml_path` names it in error messages and resolves a relative image path.
[[nodiscard]] MapServerMetadata read_map_server_yaml(std::istream& in,
                                                     const std::filesystem::path& yaml_path);

/// Reads a PGM image (binary P5 or ASCII P2, 8 or 16 bit) as a map_server map with the given metadata:
/// occupancy p = shade (negate) or 1 - shade, with shade = value / maxval; p > occupied_thresh is occupied,
/// p < free_thresh free, the rest unknown (in scale mode too: a planner has no use for the grey levels). In
/// raw mode the value is the occupancy in percent (0..100; larger values unknown). The image's top row is
/// the grid's last row, so cell (0, 0) is the lower-left pixel at `origin`. Yaw is ignored, as map_server's
/// users do. Throws MapFileError.
[[nodiscard]] OccupancyGrid read_map_server_image(const std::filesystem::path& image_path,
                                                  const MapServerMetadata& metadata);
/// The same from a stream (opened binary); `image_path` names it (its extension must be .pgm).
[[nodiscard]] OccupancyGrid read_map_server_image(std::istream& in, const std::filesystem::path& image_path,
                                                  const MapServerMetadata& metadata);

/// read_map_server_yaml then read_map_server_image.
[[nodiscard]] OccupancyGrid read_map_server_map(const std::filesystem::path& yaml_path);

}  // namespace strata::io

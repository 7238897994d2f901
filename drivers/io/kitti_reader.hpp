#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <istream>
#include <optional>
#include <string_view>
#include <vector>

#include "drivers/io/loaded_cloud.hpp"

namespace strata::io {

// The KITTI odometry benchmark's files (Geiger et al., "Are we ready for autonomous driving?", 2012):
//   velodyne/NNNNNN.bin  float32 x, y, z, reflectance per point, metres, the Velodyne's frame (x forward,
//                        y left, z up: already Strata's), no header;
//   poses.txt            one line of 12 numbers per scan: the 3x4 row-major pose of camera 0 in the frame of
//                        camera 0 at the first scan (x right, y down, z forward);
//   times.txt            one time per scan, seconds;
//   calib.txt            "Tr:" followed by 12 numbers: the Velodyne -> camera 0 transform.

/// The points of a velodyne .bin file (reflectance ignored). Throws PointFileError when the size is not a
/// whole number of 16-byte points.
[[nodiscard]] LoadedCloud read_kitti_velodyne(const std::filesystem::path& path);
/// The same from the file's bytes; `source` names them in error messages.
[[nodiscard]] LoadedCloud parse_kitti_velodyne(std::string_view bytes, const std::filesystem::path& source);

/// Every pose in a poses.txt, in order. Throws PointFileError naming the line that is not 12 numbers.
[[nodiscard]] std::vector<Eigen::Isometry3d> read_kitti_poses(const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] std::vector<Eigen::Isometry3d> read_kitti_poses(std::istream& in,
                                                              const std::filesystem::path& source);

/// Every time in a times.txt, in order. Throws PointFileError naming a line that is not one number.
[[nodiscard]] std::vector<double> read_kitti_times(const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] std::vector<double> read_kitti_times(std::istream& in, const std::filesystem::path& source);

/// The Velodyne -> camera 0 transform ("Tr:") of a calib.txt, or nothing when the file has no Tr line.
/// Throws PointFileError when the file cannot be read or the line is not 12 numbers.
[[nodiscard]] std::optional<Eigen::Isometry3d> read_kitti_velodyne_to_camera(
    const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] std::optional<Eigen::Isometry3d> read_kitti_velodyne_to_camera(
    std::istream& in, const std::filesystem::path& source);

/// The camera 0 poses of poses.txt as the Velodyne's poses in the frame of the first Velodyne pose (x
/// forward, y left, z up). With `velodyne_to_camera` (calib.txt's Tr) exactly; without, the nominal
/// mounting (the axes only, no offset).
[[nodiscard]] std::vector<Eigen::Isometry3d> kitti_velodyne_poses(
    const std::vector<Eigen::Isometry3d>& camera_poses,
    const std::optional<Eigen::Isometry3d>& velodyne_to_camera);

}  // namespace strata::io

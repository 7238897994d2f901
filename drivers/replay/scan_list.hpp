#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "drivers/replay/dataset.hpp"

namespace strata::replay {

/// The scans of a scans.csv (a Strata recording's, or a hand-made list of point files): its `file` and
/// `stamp` columns and, where present, duration, sensor, rays, max_range, the odometry and true poses, the
/// sensor's mounting (mount_00 ... mount_23), the gravity reading (up_x, up_y, up_z, up_sigma) and the
/// standing gyro (gyro_rate, gyro_seconds, gyro_sigma). File names are taken relative to `directory`;
/// `source` names the text in errors. Every field is checked, and the stamps must not go back; that the point
/// files exist is the caller's to check (open_dataset does). Throws DatasetError naming the line or the scan.
[[nodiscard]] std::vector<DatasetScan> parse_scan_list(std::istream& csv,
                                                       const std::filesystem::path& directory,
                                                       const std::string& source);

/// A transform stored as 12 numbers, 3x4 row-major (scans.csv's mount columns, recording.json's
/// initial_map_from_odom). `values` must hold 12.
[[nodiscard]] Eigen::Isometry3d transform_from_row_major(const std::vector<double>& values);

}  // namespace strata::replay

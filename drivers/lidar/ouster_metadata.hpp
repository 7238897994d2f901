#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace strata::lidar {

/// What decoding an Ouster OS-1 needs from its metadata JSON (the sensor's get_beam_intrinsics /
/// get_sensor_info answers, as drivers save them next to a recording).
struct OusterMetadata {
  std::vector<double> beam_altitude_angles;     ///< deg, one per channel (64), top beam first
  std::vector<double> beam_azimuth_angles;      ///< deg, per-beam offset from the column's encoder angle
  int columns_per_frame = 1024;                 ///< from lidar_mode "WxH": 512, 1024 or 2048
  int frequency = 10;                           ///< Hz, from lidar_mode
  double lidar_origin_to_beam_origin_mm = 0.0;  ///< firmware 1.x metadata has none: beams from the origin
  /// Lidar frame (range origin) to sensor frame (the housing's, z up), translation in mm. Legacy metadata
  /// has none; then the OS-1 default from the 1.x software user guide: turned 180 deg about z, 36.18 mm up.
  Eigen::Matrix4d lidar_to_sensor_transform;
};

/// Parses the JSON; `source` names it in errors. Throws LidarConfigError: not JSON (or nested deeper than 64
/// levels), a missing or mistyped field, angle arrays that are not 64 finite values, an unknown lidar_mode,
/// a beam origin beyond +-1000 mm, a lidar_to_sensor_transform that is not a rotation and a translation
/// within +-10,000 mm.
[[nodiscard]] OusterMetadata parse_ouster_metadata(const std::string& json_text, std::string_view source);
/// Reads and parses a metadata file. Throws LidarConfigError.
[[nodiscard]] OusterMetadata read_ouster_metadata(const std::filesystem::path& path);

}  // namespace strata::lidar

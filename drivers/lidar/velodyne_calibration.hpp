#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace strata::lidar {

/// One laser's corrections, as the velodyne_pointcloud calibration YAML gives them (angles in radians,
/// lengths in metres).
struct VelodyneLaser {
  int laser_id = 0;
  double rot_correction = 0.0;     ///< azimuth offset of this laser
  double vert_correction = 0.0;    ///< elevation
  double dist_correction = 0.0;    ///< added to every range
  double dist_correction_x = 0.0;  ///< near-range two-point corrections (read, not applied: see decoder)
  double dist_correction_y = 0.0;
  double vert_offset_correction = 0.0;   ///< the laser's height above the sensor origin
  double horiz_offset_correction = 0.0;  ///< the laser's sideways offset from the rotation axis
  double focal_distance = 0.0;           ///< intensity correction parameters (read, not applied)
  double focal_slope = 0.0;
};

/// A Velodyne calibration: lasers indexed by laser_id (the order the packet stores them in).
struct VelodyneCalibration {
  std::vector<VelodyneLaser> lasers;
  double distance_resolution = 0.002;  ///< m per raw distance unit
};

/// Parses velodyne_pointcloud's calibration YAML (`lasers:` list, optional `num_lasers`,
/// `distance_resolution`). `source` names the text in errors. Throws LidarConfigError naming the problem:
/// YAML syntax, no lasers, a missing or non-numeric field, duplicate or missing laser ids, a laser count
/// that disagrees with num_lasers, an angle beyond its range (vert_correction +-pi/2, rot_correction
/// +-2 pi) or a length correction beyond +-10 m.
[[nodiscard]] VelodyneCalibration parse_velodyne_calibration(const std::string& yaml_text,
                                                             std::string_view source);
/// Reads and parses a calibration file. Throws LidarConfigError.
[[nodiscard]] VelodyneCalibration read_velodyne_calibration(const std::filesystem::path& path);

/// The datasheets' nominal elevations (no other corrections), for running without a calibration file.
[[nodiscard]] VelodyneCalibration nominal_vlp16_calibration();
[[nodiscard]] VelodyneCalibration nominal_hdl32e_calibration();

}  // namespace strata::lidar

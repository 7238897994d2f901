#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>

#include "drivers/scan_event.hpp"

namespace strata {

/// The sensor's pose on the base, for every scan a driver hands on: as given (--lidar-mount, a scan list's
/// mount columns), else estimated once from the ground under the sensor in its first scans
/// (find_ground_plane): without it the base frame would be the sensor's, the robot drawn at the sensor's
/// height and the map's floor 1-2 m below the level it drives on. The estimate is the sensor's pose over
/// the ground the robot stands on: on a ramp, that is the ramp, which is what the base's frame means.
class SensorMount {
 public:
  /// Scans tried for the ground before the sensor's frame is kept as the base's (and a warning logged).
  static constexpr std::size_t kScansToTry = 10;

  /// `given`: the mount, or nothing to estimate it; `who`: names the source in the log ("pcap", "replay").
  SensorMount(std::optional<Eigen::Isometry3d> given, std::string who);

  /// Sets scan.sensor_to_base: the given mount, the estimate once found, else the identity (the scans
  /// before the ground was found, or all of them when it never was).
  void apply(ScanEvent& scan);

  /// The mount in use: given or estimated; nothing while it is still being looked for or was never found.
  [[nodiscard]] std::optional<Eigen::Isometry3d> mount() const { return mount_; }
  [[nodiscard]] bool estimated() const { return estimated_; }

 private:
  std::optional<Eigen::Isometry3d> mount_;
  bool estimated_ = false;
  std::string who_;
  std::size_t tried_ = 0;
};

}  // namespace strata

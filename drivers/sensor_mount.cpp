#include "drivers/sensor_mount.hpp"

#include <spdlog/spdlog.h>

#include <utility>

#include "core/points/ground_plane.hpp"

namespace strata {

SensorMount::SensorMount(std::optional<Eigen::Isometry3d> given, std::string who)
    : mount_(std::move(given)), who_(std::move(who)) {}

void SensorMount::apply(ScanEvent& scan) {
  if (!mount_ && tried_ < kScansToTry) {
    ++tried_;
    std::string why;
    if (const auto ground = find_ground_plane(scan.points, {}, &why)) {
      mount_ = ground->sensor_to_base();
      estimated_ = true;
      const Eigen::Vector2d tilt = ground->tilt_deg();
      spdlog::info(
          "{}: sensor mount estimated from the ground under it in scan {}: {:.2f} m above it, roll {:.1f}, "
          "pitch {:.1f} degrees ({} of {} thinned points on the plane); --lidar-mount sets it",
          who_, tried_, ground->height, tilt.x(), tilt.y(), ground->inliers, ground->candidates);
    } else if (tried_ < kScansToTry) {
      spdlog::info("{}: no ground under the sensor in scan {} ({}): its base frame is the sensor's", who_,
                   tried_, why);
    } else {
      spdlog::warn(
          "{}: no ground under the sensor in the first {} scans ({}): the base frame stays the sensor's, so "
          "the map's floor is the sensor's height below the robot; give --lidar-mount x,y,z",
          who_, kScansToTry, why);
    }
  }
  scan.sensor_to_base = mount_.value_or(Eigen::Isometry3d::Identity());
}

}  // namespace strata

#pragma once

#include <optional>
#include <string>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"

namespace strata {

/// A velocity command for a differential-drive base: forward speed v (m/s) and turn rate w (rad/s).
struct VelocityCommand {
  double v = 0.0;
  double w = 0.0;
  /// An operator drives by hand (teleop): a stop-and-go base scans when they let go, not under them.
  bool by_hand = false;
};

/// What the robot's base reports at one instant, from any driver (the simulator, a replay, a lidar):
/// the robot's vocabulary, next to ScanEvent, so nothing above the drivers needs the simulator's headers.
struct RobotSample {
  double stamp = 0.0;  ///< s; simulated seconds since the start, or the dataset's or sensor's clock
  Pose3 odometry;      ///< what the wheels report: planar, and it drifts
  /// The true pose where one is known: the simulator's ground truth, a replay's reference pose. For
  /// display and evaluation only, never for control.
  std::optional<Pose3> truth;
  VelocityCommand velocity;
  /// Whether `velocity` is the base's own (the simulator): a replay or a lidar alone does not know it.
  bool velocity_known = false;
  /// Which way is up, where the base has an accelerometer (the simulator's IMU): with the odometry it
  /// gives the height and tilt between scans (PoseExtrapolator). None where the driver has no IMU.
  std::optional<GravityReading> gravity;
  bool scanning = false;   ///< standing still for a stop-and-go scan
  std::string blocked_by;  ///< why the last step could not move ("step", "slope", ...), or empty
  /// A scan is due from the sensor: always for a spinning lidar and the replay and lidar drivers, for the
  /// stop-and-go scanner only while it scans. What the status's sensor watch times (a stalled sensor).
  bool awaiting_scan = true;
};

}  // namespace strata

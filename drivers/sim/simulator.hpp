#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "drivers/robot_sample.hpp"
#include "drivers/scan_event.hpp"
#include "drivers/sim/diff_drive_base.hpp"
#include "drivers/sim/imu.hpp"
#include "drivers/sim/route_driver.hpp"
#include "drivers/sim/scanners/spinning_lidar.hpp"
#include "drivers/sim/scanners/tilting_scanner.hpp"
#include "drivers/sim/terrain_base.hpp"
#include "drivers/sim/wheel_odometry.hpp"
#include "drivers/sim/world/world.hpp"

namespace strata::sim {

enum class ScannerKind {
  kTilting,  ///< the thesis robot's rotating 2D laser, stop-and-go
  kLidar,    ///< a spinning multi-beam lidar, scanning while driving
  kNone,
};

struct SimulatorConfig {
  std::uint64_t seed = 1;
  DiffDriveLimits limits;
  BaseGeometry geometry;
  OdometryNoise odometry;
  /// The base's IMU: its gyro turns the odometry, its accelerometer reports gravity with each scan. None:
  /// wheels alone, no gravity (a base without an IMU).
  std::optional<ImuNoise> imu = ImuNoise{};
  ScannerKind scanner = ScannerKind::kTilting;
  TiltingScannerConfig tilting;
  SpinningLidarConfig lidar;
  double scan_spacing = 2.0;  ///< m driven between stop-and-go scans
  double cruise_speed = 0.6;  ///< m/s along the demo route
  /// A fault drill: the sensor delivers nothing from `start` for `duration` simulated seconds (a scan that
  /// completes then is lost; the stop-and-go robot stands and tries again until a scan comes through).
  struct SensorOutage {
    double start = 0.0;
    double duration = 0.0;
  };
  std::optional<SensorOutage> sensor_outage;
};

/// The simulated robot in its world, advanced in fixed steps of simulated time. Pure and
/// single-threaded: the same seed and the same steps give the same samples and scans.
class Simulator {
 public:
  Simulator(std::shared_ptr<const World> world, SimulatorConfig config);

  void step(double dt);
  /// Drives with (v, w) from now on instead of the demo route. Once a controller has taken over, the route
  /// is not resumed: an operator's goal or teleop ends the demo for good. The command holds until the next
  /// one; stop-and-go scans still hold the robot still while they last.
  void command(const VelocityCommand& command);
  /// True until the first command(): the robot drives the world's demo route.
  [[nodiscard]] bool following_route() const { return !commanded_; }
  [[nodiscard]] RobotSample sample() const;
  /// Scans completed since the last call, oldest first.
  [[nodiscard]] std::vector<ScanEvent> take_scans();

  [[nodiscard]] const World& world() const { return *world_; }
  [[nodiscard]] const Stance& stance() const { return stance_; }
  [[nodiscard]] const SimulatorConfig& config() const { return config_; }
  /// The base's IMU, none without one: its drawn errors, for tests and benchmarks to compare against.
  [[nodiscard]] const std::optional<SimulatedImu>& imu() const { return imu_; }

 private:
  void finish_scan(ScanEvent scan);
  [[nodiscard]] bool sensor_out() const;

  std::shared_ptr<const World> world_;
  SimulatorConfig config_;
  TerrainPlacer placer_;
  DiffDriveBase base_;
  Stance stance_;
  WheelOdometry odometry_;
  std::optional<SimulatedImu> imu_;
  std::optional<GravityReading> streamed_gravity_;  ///< the IMU's reading at the last step
  /// What the gyro turned while the base stood since the last scan, and for how long (StandingGyro).
  double standing_turn_ = 0.0;
  double standing_seconds_ = 0.0;
  RouteDriver driver_;
  bool commanded_ = false;
  VelocityCommand command_;
  TiltingScanner tilting_;
  SpinningLidar lidar_;
  std::vector<ScanEvent> finished_scans_;
  double time_ = 0.0;
  double since_last_scan_ = 0.0;  // m driven since the last stop-and-go scan
  std::string blocked_by_;
};

}  // namespace strata::sim

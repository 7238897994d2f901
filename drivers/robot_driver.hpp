#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>

#include "drivers/robot_sample.hpp"
#include "drivers/scan_event.hpp"

namespace strata {

namespace sim {
class World;
}  // namespace sim

/// Where the pipeline's data comes from (the simulator, a dataset replay, later a live sensor or a packet
/// capture): a source of odometry samples and 3D scans, which may also take velocity commands and may
/// have a simulated world to show. The server runs any of them the same way (docs/architecture.md 3).
class RobotDriver {
 public:
  /// Called on the driver's thread for every odometry sample (newest state of the base).
  using SampleSink = std::function<void(const RobotSample&)>;
  /// Called on the driver's thread for every completed scan; must return at once.
  using ScanSink = std::function<void(ScanEvent)>;
  /// Blocks until the pipeline has finished every scan handed to the ScanSink so far. A source that can
  /// run faster than real time (a replay "as fast as possible") waits on it so that no scan is dropped;
  /// a live source never calls it. Returns false when the pipeline is stopping.
  using PipelineIdle = std::function<bool()>;
  /// Asked with the latest sample: a (v, w) command for the base, or nothing (leave the base as it is).
  using CommandSource = std::function<std::optional<VelocityCommand>(const RobotSample&)>;

  struct Outputs {
    SampleSink on_sample;
    ScanSink on_scan;
    PipelineIdle wait_for_pipeline;     ///< may be empty: then the source never waits
    std::function<void()> on_finished;  ///< a finite source has handed on everything; may be empty
  };

  virtual ~RobotDriver() = default;

  /// "simulator", "replay", ...: what the log and the status report.
  [[nodiscard]] virtual std::string kind() const = 0;
  /// One line for the log: what is being played or simulated.
  [[nodiscard]] virtual std::string description() const = 0;
  /// Where the odometry frame starts in the map frame (what an operator's initial pose gives).
  [[nodiscard]] virtual Eigen::Isometry3d initial_map_from_odom() const = 0;
  /// Which IMU the base's gravity readings come from, as a name that stays the same from run to run of
  /// the same robot (what its calibration is kept under); none for a source without one.
  [[nodiscard]] virtual std::optional<std::string> imu_name() const { return std::nullopt; }
  /// The simulated world, for the web app and REST; null for anything but the simulator.
  [[nodiscard]] virtual const sim::World* world() const { return nullptr; }
  /// Whether set_command_source() drives anything (false: goals and teleop have no effect on the robot).
  [[nodiscard]] virtual bool accepts_commands() const { return false; }
  /// Before start(); ignored by sources that cannot move (a replay).
  virtual void set_command_source(CommandSource /*source*/) {}

  /// Starts the driver's thread, which calls `outputs` until stop() (or until a finite source ends).
  virtual void start(Outputs outputs) = 0;
  /// Stops and joins the thread; idempotent.
  virtual void stop() = 0;
  /// A finite source (a replay) that has handed on everything it had; never true for a live one.
  [[nodiscard]] virtual bool finished() const { return false; }
};

}  // namespace strata

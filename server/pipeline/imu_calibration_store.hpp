#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>

#include "core/localization/pose_graph_status.hpp"
#include "server/control/robot_commands.hpp"

namespace strata::pipeline {

/// What a run learnt of the base's IMU that holds for the next run of the same robot: how its
/// accelerometer is mounted. The scan path learns it only as the robot turns, and until then tilts the
/// way by it: over ten campus runs the height was 0.12 m off on average, 0.08 m when each started from
/// what its first run kept (docs/benchmarks.md, "IMU calibration kept between runs"). The gyro's bias is
/// not kept: it changes with every start and with the temperature.
struct ImuCalibration {
  std::string imu;  ///< which IMU it is (RobotDriver::imu_name)
  /// The accelerometer's mounting error about the base's x and y axes (roll, pitch), radians: what
  /// GraphLocalizer::start_from_calibration takes.
  Eigen::Vector2d mounting = Eigen::Vector2d::Zero();
  std::size_t loops = 0;      ///< loop closures in the pose graph that estimated it
  std::size_t keyframes = 0;  ///< keyframes in that graph
};

/// The calibration file: one IMU's calibration as JSON (docs/architecture.md 4.1). Throws
/// std::runtime_error naming the file and what is wrong with it when it is no such file.
[[nodiscard]] ImuCalibration parse_imu_calibration(const std::string& text);
[[nodiscard]] std::string format_imu_calibration(const ImuCalibration& calibration);

/// Keeps the IMU calibration of this server's robot in one file: read at start, written (atomically, the
/// old file survives a crash) each time a loop closure confirms the pose graph's estimate, removed on
/// request. Kept under the IMU's name: another robot's file is not used, and is replaced at its first save.
/// Thread-safe: the pose graph's thread saves, the network's threads read and clear.
class ImuCalibrationStore final : public CalibrationCommands {
 public:
  /// Keeps nothing: a base without an IMU, or keeping turned off.
  ImuCalibrationStore() = default;
  /// Keeps the calibration of `imu` in `file`.
  ImuCalibrationStore(std::filesystem::path file, std::string imu);

  /// What to start from: the file's calibration when it is this IMU's. A file that cannot be read, or is
  /// another IMU's, is logged and not used (the run learns afresh).
  [[nodiscard]] std::optional<ImuCalibration> load();
  /// After a pose graph optimization: keeps its mounting estimate when more loop closures confirm it than
  /// the last one this run kept. Logs a failure to write; the run goes on.
  void update(const PoseGraphStatus& graph);

  [[nodiscard]] ImuCalibrationStatus imu_calibration() const override;
  CommandResult clear_imu_calibration() override;

 private:
  std::filesystem::path file_;
  mutable std::mutex mutex_;
  ImuCalibrationStatus status_;
  std::size_t saved_loops_ = 0;  ///< loops of the last estimate this run kept
};

}  // namespace strata::pipeline

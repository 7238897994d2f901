#pragma once

#include <cstddef>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>

#include "core/localization/pose_graph_status.hpp"
#include "server/control/robot_commands.hpp"
#include "server/pipeline/imu_calibration_file.hpp"

namespace strata::pipeline {

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

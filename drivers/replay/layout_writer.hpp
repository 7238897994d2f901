#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "drivers/replay/recording_writer.hpp"

namespace strata::replay {

/// recording.json's content (the MCAP recording's /strata/recording too): `metadata` with the format, its
/// version, the initial pose (3x4 row-major) and when the recording started.
[[nodiscard]] nlohmann::json recording_metadata(const nlohmann::json& metadata,
                                                const Eigen::Isometry3d& initial_map_from_odom);

/// Strata's own recording layout (recording_layout.hpp) in a directory: `strata serve --record DIR`.
class LayoutWriter final : public RecordingWriter {
 public:
  /// Creates `directory` (and scans/) and writes recording.json with `metadata` (source, seed, ...) and the
  /// initial pose. Throws std::runtime_error when the directory cannot be made or already holds a recording.
  LayoutWriter(std::filesystem::path directory, const nlohmann::json& metadata,
               const Eigen::Isometry3d& initial_map_from_odom);

  using RecordingWriter::write;  // a TopicMessage: not in this layout
  void write(const RobotSample& sample) override;
  void write(const ScanEvent& scan) override;
  /// Completes recording.json.
  void finish(const RecorderStatus& status) override;
  [[nodiscard]] std::string where() const override { return directory_.string(); }

 private:
  void write_metadata(bool finished, const RecorderStatus& status);

  std::filesystem::path directory_;
  nlohmann::json metadata_;
  std::ofstream scans_csv_;
  std::ofstream odometry_csv_;
  std::size_t next_scan_file_ = 0;
};

}  // namespace strata::replay

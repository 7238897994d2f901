#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "drivers/mcap/mcap_writer.hpp"
#include "drivers/replay/recording_writer.hpp"

namespace strata::replay {

/// Records the run as an MCAP file of ROS 2 messages (mcap_recording_layout.hpp): `strata serve
/// --record-mcap FILE`. While it runs the file is FILE.part, written chunk by chunk (a chunk closes with
/// every scan), so a killed server leaves a file every MCAP reader reads up to its last chunk; a clean
/// stop writes the summary and renames it to FILE.
class McapRecordingWriter final : public RecordingWriter {
 public:
  /// Throws std::runtime_error when FILE exists or FILE.part cannot be written.
  McapRecordingWriter(std::filesystem::path file, const nlohmann::json& metadata,
                      const Eigen::Isometry3d& initial_map_from_odom, mcap::Compression compression);

  void write(const RobotSample& sample) override;
  void write(const ScanEvent& scan) override;
  void write(const TopicMessage& message) override;
  [[nodiscard]] bool keeps_topic_messages() const override { return true; }
  void finish(const RecorderStatus& status) override;
  [[nodiscard]] std::string where() const override { return file_.string(); }

  /// The file being written until finish().
  [[nodiscard]] static std::filesystem::path partial_path(const std::filesystem::path& file);

 private:
  /// The channel of `topic` (made on first use, with the type's ros2msg schema).
  std::uint16_t channel(std::string_view topic, std::string_view type);
  void add(std::string_view topic, std::string_view type, double stamp, const std::vector<std::uint8_t>& cdr);
  void write_row(std::string_view topic, double stamp, std::string row);
  /// Appends what the writer has written since the last call.
  void write_out();

  std::filesystem::path file_;
  std::filesystem::path partial_;
  std::ofstream out_;
  mcap::McapWriter writer_;
  std::map<std::string, std::uint16_t, std::less<>> schemas_;
  std::map<std::string, std::uint16_t, std::less<>> channels_;
};

}  // namespace strata::replay

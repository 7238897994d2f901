#include "drivers/replay/mcap_dataset.hpp"

#include <spdlog/fmt/fmt.h>

#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "drivers/mcap/mcap_reader.hpp"
#include "drivers/replay/mcap_recording_layout.hpp"
#include "drivers/replay/scan_list.hpp"
#include "drivers/ros2/cdr_reader.hpp"
#include "drivers/ros2/message_decoding.hpp"

namespace strata::replay {
namespace {

std::span<const std::uint8_t> bytes_of(const std::string& data) {
  return {reinterpret_cast<const std::uint8_t*>(data.data()), data.size()};
}

/// The messages of one topic, in file order (their sequence order: one writer, one thread).
std::vector<mcap::McapMessage> messages_on(const mcap::McapReader& reader, std::string_view topic,
                                           const std::string& source) {
  const mcap::McapChannel* channel = reader.channel(topic);
  if (channel == nullptr)
    throw DatasetError(source + ": no " + std::string(topic) + " channel (not a Strata MCAP recording)");
  std::vector<mcap::McapMessage> messages;
  for (const mcap::McapMessage& message : reader.messages()) {
    if (message.channel_id == channel->id)
      messages.push_back(message);
  }
  return messages;
}

/// The scans' points: the /scan messages, read and decoded when played.
class McapScanStore final : public ScanStore {
 public:
  McapScanStore(mcap::McapReader reader, std::vector<mcap::McapMessage> scans)
      : reader_(std::move(reader)), scans_(std::move(scans)) {}

  std::vector<Eigen::Vector3f> points(std::size_t index, std::vector<float>* times) override {
    std::lock_guard lock(mutex_);
    try {
      const std::string data = reader_.message_data(scans_.at(index));
      const ros2::PointCloud2 cloud = ros2::decode_point_cloud(bytes_of(data));
      return unpacked(cloud, times);
    } catch (const std::exception& e) {
      throw DatasetError(fmt::format("the /scan message of scan {}: {}", index, e.what()));
    }
  }

 private:
  /// x, y, z (and time) as the recorder packs them: float32 at offsets 0, 4, 8 (12).
  static std::vector<Eigen::Vector3f> unpacked(const ros2::PointCloud2& cloud, std::vector<float>* times) {
    const bool timed = cloud.fields.size() == 4 && cloud.fields[3].name == "time";
    const std::uint32_t step = timed ? 16 : 12;
    const std::size_t count = static_cast<std::size_t>(cloud.width) * cloud.height;
    if (cloud.point_step != step || cloud.data.size() != count * step || cloud.fields.size() < 3 ||
        cloud.fields[0].name != "x" || cloud.fields[1].name != "y" || cloud.fields[2].name != "z")
      throw DatasetError("not a cloud of x, y, z (time) float32 points as Strata records them");
    std::vector<Eigen::Vector3f> points(count);
    if (times != nullptr)
      times->assign(timed ? count : 0, 0.0F);
    const std::uint8_t* in = cloud.data.data();
    for (std::size_t i = 0; i < count; ++i, in += step) {
      std::memcpy(points[i].data(), in, 12);
      if (timed && times != nullptr)
        std::memcpy(&(*times)[i], in + 12, 4);
    }
    return points;
  }

  std::mutex mutex_;
  mcap::McapReader reader_;
  std::vector<mcap::McapMessage> scans_;
};

/// The rows on `topic` as one CSV text under `header`.
std::string csv_of(mcap::McapReader& reader, const std::vector<mcap::McapMessage>& rows,
                   const std::string& header) {
  std::string csv = header;
  for (const mcap::McapMessage& row : rows)
    csv += ros2::decode_string(bytes_of(reader.message_data(row))).data + "\n";
  return csv;
}

}  // namespace

Dataset open_mcap_recording(const std::filesystem::path& file) {
  const std::string source = file.string();
  try {
    mcap::McapReader reader(file);
    const auto recording = messages_on(reader, kRecordingTopic, source);
    const auto scan_rows = messages_on(reader, kScanRowsTopic, source);
    const auto odometry_rows = messages_on(reader, kOdometryRowsTopic, source);
    const auto scans = messages_on(reader, kScanTopic, source);
    if (recording.size() != 1)
      throw DatasetError(source + ": " + std::to_string(recording.size()) +
                         " /strata/recording messages (one)");
    if (scans.size() != scan_rows.size())
      throw DatasetError(fmt::format("{}: {} /scan messages for {} /strata/scans rows", source, scans.size(),
                                     scan_rows.size()));
    const std::string metadata_text = ros2::decode_string(bytes_of(reader.message_data(recording[0]))).data;
    const nlohmann::json metadata = nlohmann::json::parse(metadata_text, nullptr, false);
    if (!metadata.is_object() || !metadata.contains("scans_csv_header") ||
        !metadata.contains("odometry_csv_header") || !metadata["scans_csv_header"].is_string() ||
        !metadata["odometry_csv_header"].is_string())
      throw DatasetError(source + ": /strata/recording has no CSV headers");

    Dataset dataset;
    dataset.layout = DatasetLayout::kMcap;
    dataset.directory = file;
    std::istringstream scan_csv(csv_of(reader, scan_rows, metadata["scans_csv_header"].get<std::string>()));
    dataset.scans = parse_scan_list(scan_csv, file.parent_path(), source + " /strata/scans");
    std::istringstream odometry_csv(
        csv_of(reader, odometry_rows, metadata["odometry_csv_header"].get<std::string>()));
    dataset.odometry = parse_odometry_stream(odometry_csv, source + " /strata/odometry");
    read_recording_metadata(metadata_text, source + " /strata/recording", kMcapRecordingFormat,
                            kMcapRecordingVersion, dataset);
    dataset.description = "an MCAP " + dataset.description.substr(2);  // "a Strata recording ..."
    const auto store = std::make_shared<McapScanStore>(std::move(reader), scans);
    for (std::size_t i = 0; i < dataset.scans.size(); ++i) {
      dataset.scans[i].file = file;
      dataset.scans[i].store = store;
      dataset.scans[i].store_index = i;
    }
    return dataset;
  } catch (const DatasetError&) {
    throw;
  } catch (const std::exception& e) {  // McapError, CdrError
    throw DatasetError(e.what());
  }
}

}  // namespace strata::replay

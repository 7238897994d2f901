#include "drivers/ros2/map_messages.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <map>
#include <optional>

#include "core/mls/map_export.hpp"
#include "drivers/ros2/message_encoding.hpp"
#include "drivers/ros2/message_schemas.hpp"

namespace strata::ros2 {
namespace {

/// One point of patch_cloud, as laid out in its data (20 bytes: the floats stay 4-aligned).
struct PatchPoint {
  float x, y, z, height;
  std::uint8_t patch_class, level, padding[2];
};
static_assert(sizeof(PatchPoint) == 20);

enum PatchClass : std::uint8_t { kFloor = 0, kVertical = 1, kDriven = 2 };

/// Writes `message` on a channel of its own (topic, schema) at `stamp_ns`.
template <typename Message>
void write_message(mcap::McapWriter& writer, std::string_view topic, const Message& message,
                   std::uint64_t stamp_ns) {
  const std::uint16_t schema =
      writer.add_schema(Message::kType, "ros2msg", ros2msg_definition(Message::kType));
  const std::uint16_t channel = writer.add_channel(schema, topic, "cdr", latched_channel_metadata());
  writer.add_message(channel, stamp_ns, stamp_ns, encode(message));
}

}  // namespace

const std::map<std::string, std::string>& latched_channel_metadata() {
  static const std::map<std::string, std::string> latched = {
      {"offered_qos_profiles",
       "- history: 1\n  depth: 1\n  reliability: 1\n  durability: 1\n  deadline:\n    sec: 2147483647\n"
       "    nsec: 4294967295\n  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n  liveliness: 1\n"
       "  liveliness_lease_duration:\n    sec: 2147483647\n    nsec: 4294967295\n"
       "  avoid_ros_namespace_conventions: false\n"}};
  return latched;
}

PointCloud2 patch_cloud(const MlsMap& map, const Header& header) {
  PointCloud2 cloud;
  cloud.header = header;
  cloud.fields = {{"x", offsetof(PatchPoint, x), PointField::kFloat32, 1},
                  {"y", offsetof(PatchPoint, y), PointField::kFloat32, 1},
                  {"z", offsetof(PatchPoint, z), PointField::kFloat32, 1},
                  {"height", offsetof(PatchPoint, height), PointField::kFloat32, 1},
                  {"class", offsetof(PatchPoint, patch_class), PointField::kUint8, 1},
                  {"level", offsetof(PatchPoint, level), PointField::kUint8, 1}};
  cloud.point_step = sizeof(PatchPoint);
  cloud.data.reserve(map.patch_count() * sizeof(PatchPoint));
  std::optional<CellIndex> last_cell;
  int level = 0;
  for_each_patch(map, [&](const CellIndex& cell, const MlsPatch& patch) {  // each cell's lowest first
    level = last_cell == cell ? level + 1 : 0;
    last_cell = cell;
    const Eigen::Vector2d centre = map.cell_center(cell);
    const PatchPoint point{static_cast<float>(centre.x()),
                           static_cast<float>(centre.y()),
                           patch.mean,
                           patch.depth,
                           patch.vertical() ? kVertical
                           : patch.driven() ? kDriven
                                            : kFloor,
                           static_cast<std::uint8_t>(std::min(level, 255)),
                           {0, 0}};
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(&point);
    cloud.data.insert(cloud.data.end(), bytes, bytes + sizeof(point));
  });
  cloud.width = static_cast<std::uint32_t>(cloud.data.size() / sizeof(PatchPoint));
  cloud.row_step = static_cast<std::uint32_t>(cloud.data.size());
  return cloud;
}

OccupancyGrid occupancy_grid(const LevelGrid& grid, const Header& header) {
  OccupancyGrid message;
  message.header = header;
  message.map_load_time = header.stamp;
  message.resolution = static_cast<float>(grid.resolution);
  message.width = static_cast<std::uint32_t>(grid.width);
  message.height = static_cast<std::uint32_t>(grid.height);
  message.origin.translation() = Eigen::Vector3d(grid.origin.x(), grid.origin.y(), 0.0);
  message.data.reserve(grid.cells.size());
  for (const Occupancy cell : grid.cells)
    message.data.push_back(static_cast<std::int8_t>(cell));  // the enum's values are ROS's
  return message;
}

std::uint64_t system_time_ns() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(now).count());
}

std::string map_as_mcap(const MapRecordingContent& content, mcap::Compression compression) {
  mcap::McapWriter writer({.compression = compression});
  const Header header{Time::from_nanoseconds(content.stamp_ns), std::string(kMapFrame)};
  write_message(writer, "/map_patches", patch_cloud(*content.map, header), content.stamp_ns);
  if (content.drivable != nullptr)
    write_message(writer, "/map", occupancy_grid(*content.drivable, header), content.stamp_ns);
  if (!content.trajectory.empty()) {
    Path path;
    path.header = header;
    for (const Eigen::Isometry3d& pose : content.trajectory)
      path.poses.push_back({header, pose});
    write_message(writer, "/trajectory", path, content.stamp_ns);
    TFMessage tf;
    tf.transforms.push_back({header, std::string(kBaseFrame), content.trajectory.back()});
    write_message(writer, "/tf", tf, content.stamp_ns);
  }
  writer.finish();
  return writer.take_output();
}

}  // namespace strata::ros2

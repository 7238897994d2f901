#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <span>
#include <string>

#include "core/mls/level_grid.hpp"
#include "core/mls/mls_map.hpp"
#include "drivers/mcap/mcap_writer.hpp"
#include "drivers/ros2/messages.hpp"

namespace strata::ros2 {

/// The map frame's name in every message: the frame the MLS map, the drivable map and the poses are in.
inline constexpr std::string_view kMapFrame = "map";
/// The robot's frame, as ROS names it (REP 105).
inline constexpr std::string_view kBaseFrame = "base_link";

/// The MLS map's patches as points (map frame): x, y the cell's centre and z the patch's top (float32);
/// `height` how far a vertical patch reaches down from z (float32, 0 for a floor); `class` 0 floor,
/// 1 vertical (a wall, a step's face), 2 floor the robot drove on (uint8); `level` the patch's place in
/// its cell counted from the lowest, 0 (uint8: a bridge's road 0, its deck 1).
[[nodiscard]] PointCloud2 patch_cloud(const MlsMap& map, const Header& header);

/// The drivable map as nav_msgs/OccupancyGrid: the same cells, origin and resolution as the ROS map_server
/// export of it (core/mls/map_export.hpp), rows from the lowest y, 0 free, 100 occupied, -1 unknown.
[[nodiscard]] OccupancyGrid occupancy_grid(const LevelGrid& grid, const Header& header);

/// The ros2 profile's channel metadata of a latched topic (a map): rosbag2 replays it with the QoS offered,
/// reliable and transient local, depth 1, as map_server publishes /map.
[[nodiscard]] const std::map<std::string, std::string>& latched_channel_metadata();

/// Now, in nanoseconds since the Unix epoch: a file's stamp, as rosbag2 records with the system clock.
[[nodiscard]] std::uint64_t system_time_ns();

/// What a map download as MCAP holds.
struct MapRecordingContent {
  const MlsMap* map = nullptr;                    ///< the patches (required)
  const LevelGrid* drivable = nullptr;            ///< the drivable map at the robot's level; none: left out
  std::span<const Eigen::Isometry3d> trajectory;  ///< keyframe poses, oldest first (map frame); may be empty
  std::uint64_t stamp_ns = 0;                     ///< every message's log time and header stamp
};

/// The map as one MCAP file (ros2 profile, CDR messages, ros2msg schemas), every message at `stamp_ns`:
/// /map_patches (PointCloud2, patch_cloud), /map (OccupancyGrid at the robot's level), /trajectory
/// (nav_msgs/Path of the keyframes) and /tf (map -> base_link at the last keyframe). Topics without
/// content (no drivable map, no keyframes) are left out.
[[nodiscard]] std::string map_as_mcap(const MapRecordingContent& content, mcap::Compression compression);

}  // namespace strata::ros2

#pragma once

#include <cstdint>
#include <vector>

#include "drivers/ros2/messages.hpp"

namespace strata::ros2 {

/// Each message as CDR (cdr_writer.hpp), the bytes of an MCAP message record on a "cdr" channel and of
/// a message rosbag2 plays.
[[nodiscard]] std::vector<std::uint8_t> encode(const OccupancyGrid& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const PointCloud2& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const TFMessage& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const PoseStamped& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const PoseWithCovarianceStamped& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const Path& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const Odometry& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const Imu& message);
[[nodiscard]] std::vector<std::uint8_t> encode(const String& message);

}  // namespace strata::ros2

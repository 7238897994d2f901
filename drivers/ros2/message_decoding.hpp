#pragma once

#include <cstdint>
#include <span>

#include "drivers/ros2/messages.hpp"

namespace strata::ros2 {

/// The messages a replay reads back from CDR (what encode() wrote). Throw CdrError when the bytes do not
/// hold the message.
[[nodiscard]] PointCloud2 decode_point_cloud(std::span<const std::uint8_t> bytes);
[[nodiscard]] String decode_string(std::span<const std::uint8_t> bytes);

}  // namespace strata::ros2

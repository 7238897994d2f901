#pragma once

#include <string>
#include <string_view>

namespace strata::ros2 {

/// The complete `ros2msg` definition of `type` ("nav_msgs/msg/OccupancyGrid"), as an MCAP Schema record
/// and rosbag2 carry it: the type's own .msg text first, then every type it uses, at any depth, once
/// each, each after a line of 80 '=' and a line "MSG: pkg/Type". Field types are written "pkg/Type", as
/// the MSG lines name them, so a reader (Foxglove's) matches the two exactly. Throws std::invalid_argument
/// for a type this table does not have.
[[nodiscard]] std::string ros2msg_definition(std::string_view type);

}  // namespace strata::ros2

// The ros2msg texts an MCAP Schema record carries: the type's own fields first, then every type it uses,
// once each, after an 80-character '=' line and a "MSG: pkg/Type" line.
#include "drivers/ros2/message_schemas.hpp"

#include <gtest/gtest.h>

#include <string>

#include "drivers/ros2/messages.hpp"

namespace strata::ros2 {
namespace {

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1))
    ++count;
  return count;
}

TEST(MessageSchemas, PathHasItsFieldsFirstThenEachDependencyOnce) {
  const std::string text = ros2msg_definition(Path::kType);
  EXPECT_EQ(text.rfind("std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n", 0), 0U) << text;
  const std::string separator = std::string(80, '=') + "\n";
  for (const char* type : {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseStamped",
                           "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion"})
    EXPECT_EQ(occurrences(text, separator + "MSG: " + type + "\n"), 1U) << type << " in\n" << text;
  EXPECT_EQ(occurrences(text, "MSG: "), 6U);
  EXPECT_EQ(occurrences(text, "=" + separator), 0U);  // exactly 80
}

TEST(MessageSchemas, EveryWrittenTypeHasACompleteDefinition) {
  for (const std::string_view type :
       {OccupancyGrid::kType, PointCloud2::kType, TFMessage::kType, PoseStamped::kType,
        PoseWithCovarianceStamped::kType, Path::kType, Odometry::kType}) {
    const std::string text = ros2msg_definition(type);
    EXPECT_EQ(text.find("MSG: " + std::string(type)), std::string::npos) << "not its own dependency";
    EXPECT_NE(text.find("MSG: std_msgs/Header\n"), std::string::npos) << type;
  }
  EXPECT_NE(ros2msg_definition(PointCloud2::kType).find("uint8 FLOAT32=7\n"), std::string::npos);
}

TEST(MessageSchemas, RefusesUnknownTypes) {
  EXPECT_THROW((void)ros2msg_definition("nav_msgs/msg/GridCells"), std::invalid_argument);
  EXPECT_THROW((void)ros2msg_definition("nav_msgs/Path"), std::invalid_argument);
}

}  // namespace
}  // namespace strata::ros2

#include "drivers/ros2/message_schemas.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace strata::ros2 {
namespace {

struct Definition {
  std::string_view type;  ///< "pkg/Type", as fields and MSG lines name it
  std::string_view text;  ///< its own .msg fields
};

// The fields of each message in .msg syntax (the ROS 2 interface definitions, comments left out).
constexpr Definition kDefinitions[] = {
    {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
    {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
    {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
    {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
    {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
    {"geometry_msgs/Pose", "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"},
    {"geometry_msgs/Transform", "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"},
    {"geometry_msgs/TransformStamped",
     "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"},
    {"geometry_msgs/PoseStamped", "std_msgs/Header header\ngeometry_msgs/Pose pose\n"},
    {"geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose pose\nfloat64[36] covariance\n"},
    {"geometry_msgs/PoseWithCovarianceStamped",
     "std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n"},
    {"geometry_msgs/Twist", "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n"},
    {"geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist twist\nfloat64[36] covariance\n"},
    {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
    {"nav_msgs/MapMetaData",
     "builtin_interfaces/Time map_load_time\nfloat32 resolution\nuint32 width\nuint32 height\n"
     "geometry_msgs/Pose origin\n"},
    {"nav_msgs/OccupancyGrid", "std_msgs/Header header\nnav_msgs/MapMetaData info\nint8[] data\n"},
    {"nav_msgs/Path", "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n"},
    {"nav_msgs/Odometry",
     "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
     "geometry_msgs/TwistWithCovariance twist\n"},
    {"sensor_msgs/PointField",
     "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\nuint8 UINT32=6\n"
     "uint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\nuint8 datatype\nuint32 count\n"},
    {"sensor_msgs/PointCloud2",
     "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\n"
     "bool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n"},
    {"sensor_msgs/Imu",
     "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n"
     "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n"
     "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n"},
    {"std_msgs/String", "string data\n"},
};

const Definition& definition_of(std::string_view type) {
  const auto* found = std::find_if(std::begin(kDefinitions), std::end(kDefinitions),
                                   [&](const Definition& definition) { return definition.type == type; });
  if (found == std::end(kDefinitions))
    throw std::invalid_argument("no ros2msg definition of " + std::string(type));
  return *found;
}

/// The message types `definition`'s fields use ("pkg/Type", arrays' element types), in field order.
std::vector<std::string_view> used_types(const Definition& definition) {
  std::vector<std::string_view> used;
  std::string_view text = definition.text;
  while (!text.empty()) {
    const std::string_view line = text.substr(0, text.find('\n'));
    text.remove_prefix(std::min(text.size(), line.size() + 1));
    const std::string_view field_type = line.substr(0, std::min(line.find(' '), line.find('[')));
    if (field_type.find('/') != std::string_view::npos)
      used.push_back(definition_of(field_type).type);
  }
  return used;
}

/// Depth first, each type once: the order a reader needs none of, and rosbag2 writes likewise.
void collect(std::string_view type, std::vector<std::string_view>& seen) {
  for (const std::string_view used : used_types(definition_of(type))) {
    if (std::find(seen.begin(), seen.end(), used) != seen.end())
      continue;
    seen.push_back(used);
    collect(used, seen);
  }
}

}  // namespace

std::string ros2msg_definition(std::string_view type) {
  // "pkg/msg/Type" -> "pkg/Type".
  constexpr std::string_view kMsg = "/msg/";
  const std::size_t msg = type.find(kMsg);
  if (msg == std::string_view::npos)
    throw std::invalid_argument("a ROS 2 message type is pkg/msg/Type, not " + std::string(type));
  const std::string short_type =
      std::string(type.substr(0, msg)) + "/" + std::string(type.substr(msg + kMsg.size()));

  std::string text(definition_of(short_type).text);
  std::vector<std::string_view> dependencies;
  collect(short_type, dependencies);
  for (const std::string_view dependency : dependencies) {
    text += std::string(80, '=') + "\nMSG: " + std::string(dependency) + "\n";
    text += definition_of(dependency).text;
  }
  return text;
}

}  // namespace strata::ros2

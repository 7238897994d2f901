#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

// The ROS 2 messages Strata writes (MCAP files; later a live Foxglove endpoint), field for field as their
// .msg definitions (message_schemas.cpp) have them. A pose or transform is an Eigen::Isometry3d: it is
// written as position (or translation) and a unit quaternion. Each message names its ROS 2 type.
namespace strata::ros2 {

/// builtin_interfaces/Time.
struct Time {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  [[nodiscard]] static Time from_nanoseconds(std::uint64_t nanoseconds);
};

/// std_msgs/Header.
struct Header {
  Time stamp;
  std::string frame_id;
};

/// A float64[36] covariance, row by row (x, y, z, rotation about x, y, z); zeros: unknown.
using Covariance = std::array<double, 36>;

struct PoseWithCovariance {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Covariance covariance{};
};

struct Twist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

struct TwistWithCovariance {
  Twist twist;
  Covariance covariance{};
};

struct OccupancyGrid {
  static constexpr std::string_view kType = "nav_msgs/msg/OccupancyGrid";
  Header header;
  Time map_load_time;
  float resolution = 0.0F;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< cell (0, 0)'s corner
  std::vector<std::int8_t> data;  ///< row by row from the origin: 0 free, 100 occupied, -1 unknown
};

/// sensor_msgs/PointField.
struct PointField {
  enum Datatype : std::uint8_t {
    kInt8 = 1,
    kUint8 = 2,
    kInt16 = 3,
    kUint16 = 4,
    kInt32 = 5,
    kUint32 = 6,
    kFloat32 = 7,
    kFloat64 = 8
  };
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = kFloat32;
  std::uint32_t count = 1;
};

struct PointCloud2 {
  static constexpr std::string_view kType = "sensor_msgs/msg/PointCloud2";
  Header header;
  std::uint32_t height = 1;  ///< 1: an unordered cloud
  std::uint32_t width = 0;
  std::vector<PointField> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = true;  ///< no invalid points
};

/// geometry_msgs/TransformStamped: `transform` takes a point from child_frame_id to header.frame_id.
struct TransformStamped {
  Header header;
  std::string child_frame_id;
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
};

struct TFMessage {
  static constexpr std::string_view kType = "tf2_msgs/msg/TFMessage";
  std::vector<TransformStamped> transforms;
};

struct PoseStamped {
  static constexpr std::string_view kType = "geometry_msgs/msg/PoseStamped";
  Header header;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

struct PoseWithCovarianceStamped {
  static constexpr std::string_view kType = "geometry_msgs/msg/PoseWithCovarianceStamped";
  Header header;
  PoseWithCovariance pose;
};

struct Path {
  static constexpr std::string_view kType = "nav_msgs/msg/Path";
  Header header;
  std::vector<PoseStamped> poses;
};

struct Odometry {
  static constexpr std::string_view kType = "nav_msgs/msg/Odometry";
  Header header;
  std::string child_frame_id;
  PoseWithCovariance pose;
  TwistWithCovariance twist;  ///< in child_frame_id
};

/// sensor_msgs/Imu: a covariance's first element -1 says the reading is not there (ROS's convention).
struct Imu {
  static constexpr std::string_view kType = "sensor_msgs/msg/Imu";
  Header header;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::array<double, 9> orientation_covariance{};
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  std::array<double, 9> angular_velocity_covariance{};
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();
  std::array<double, 9> linear_acceleration_covariance{};
};

/// std_msgs/String: text (here JSON or a CSV row) for what no standard message carries.
struct String {
  static constexpr std::string_view kType = "std_msgs/msg/String";
  std::string data;
};

}  // namespace strata::ros2

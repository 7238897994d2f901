#include "drivers/ros2/message_encoding.hpp"

#include <span>

#include "drivers/ros2/cdr_writer.hpp"

namespace strata::ros2 {
namespace {

// The nested types, in their .msg field order.

void write(CdrWriter& out, const Time& time) {
  out.write(time.sec);
  out.write(time.nanosec);
}

void write(CdrWriter& out, const Header& header) {
  write(out, header.stamp);
  out.write_string(header.frame_id);
}

void write_vector(CdrWriter& out, const Eigen::Vector3d& vector) {
  out.write(vector.x());
  out.write(vector.y());
  out.write(vector.z());
}

void write_rotation(CdrWriter& out, const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond rotation(pose.rotation());
  out.write(rotation.x());
  out.write(rotation.y());
  out.write(rotation.z());
  out.write(rotation.w());
}

/// geometry_msgs/Pose and geometry_msgs/Transform alike: a point (or vector) and a quaternion.
void write_pose(CdrWriter& out, const Eigen::Isometry3d& pose) {
  write_vector(out, pose.translation());
  write_rotation(out, pose);
}

void write(CdrWriter& out, const PoseWithCovariance& pose) {
  write_pose(out, pose.pose);
  out.write_doubles(pose.covariance);
}

void write(CdrWriter& out, const TwistWithCovariance& twist) {
  write_vector(out, twist.twist.linear);
  write_vector(out, twist.twist.angular);
  out.write_doubles(twist.covariance);
}

void write(CdrWriter& out, const PoseStamped& pose) {
  write(out, pose.header);
  write_pose(out, pose.pose);
}

}  // namespace

std::vector<std::uint8_t> encode(const OccupancyGrid& message) {
  CdrWriter out;
  write(out, message.header);
  write(out, message.map_load_time);
  out.write(message.resolution);
  out.write(message.width);
  out.write(message.height);
  write_pose(out, message.origin);
  // int8 cells as the bytes they are (unsigned char may view any object).
  const auto* cells = reinterpret_cast<const std::uint8_t*>(message.data.data());
  out.write_byte_sequence({cells, message.data.size()});
  return out.take();
}

std::vector<std::uint8_t> encode(const PointCloud2& message) {
  CdrWriter out;
  write(out, message.header);
  out.write(message.height);
  out.write(message.width);
  out.write_sequence_size(message.fields.size());
  for (const PointField& field : message.fields) {
    out.write_string(field.name);
    out.write(field.offset);
    out.write(field.datatype);
    out.write(field.count);
  }
  out.write_bool(message.is_bigendian);
  out.write(message.point_step);
  out.write(message.row_step);
  out.write_byte_sequence(message.data);
  out.write_bool(message.is_dense);
  return out.take();
}

std::vector<std::uint8_t> encode(const TFMessage& message) {
  CdrWriter out;
  out.write_sequence_size(message.transforms.size());
  for (const TransformStamped& transform : message.transforms) {
    write(out, transform.header);
    out.write_string(transform.child_frame_id);
    write_pose(out, transform.transform);
  }
  return out.take();
}

std::vector<std::uint8_t> encode(const PoseStamped& message) {
  CdrWriter out;
  write(out, message);
  return out.take();
}

std::vector<std::uint8_t> encode(const PoseWithCovarianceStamped& message) {
  CdrWriter out;
  write(out, message.header);
  write(out, message.pose);
  return out.take();
}

std::vector<std::uint8_t> encode(const Path& message) {
  CdrWriter out;
  write(out, message.header);
  out.write_sequence_size(message.poses.size());
  for (const PoseStamped& pose : message.poses)
    write(out, pose);
  return out.take();
}

std::vector<std::uint8_t> encode(const Odometry& message) {
  CdrWriter out;
  write(out, message.header);
  out.write_string(message.child_frame_id);
  write(out, message.pose);
  write(out, message.twist);
  return out.take();
}

std::vector<std::uint8_t> encode(const Imu& message) {
  CdrWriter out;
  write(out, message.header);
  out.write(message.orientation.x());
  out.write(message.orientation.y());
  out.write(message.orientation.z());
  out.write(message.orientation.w());
  out.write_doubles(message.orientation_covariance);
  write_vector(out, message.angular_velocity);
  out.write_doubles(message.angular_velocity_covariance);
  write_vector(out, message.linear_acceleration);
  out.write_doubles(message.linear_acceleration_covariance);
  return out.take();
}

std::vector<std::uint8_t> encode(const String& message) {
  CdrWriter out;
  out.write_string(message.data);
  return out.take();
}

Time Time::from_nanoseconds(std::uint64_t nanoseconds) {
  return {static_cast<std::int32_t>(nanoseconds / 1'000'000'000U),
          static_cast<std::uint32_t>(nanoseconds % 1'000'000'000U)};
}

}  // namespace strata::ros2

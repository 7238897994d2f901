#include "drivers/replay/mcap_recording_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "drivers/replay/layout_writer.hpp"
#include "drivers/replay/mcap_recording_layout.hpp"
#include "drivers/replay/recording_layout.hpp"
#include "drivers/ros2/map_messages.hpp"
#include "drivers/ros2/message_encoding.hpp"
#include "drivers/ros2/message_schemas.hpp"

namespace strata::replay {
namespace fs = std::filesystem;

namespace {

constexpr double kStandardGravity = 9.80665;  // m/s^2: what an accelerometer at rest reads, upwards

std::uint64_t nanoseconds(double stamp) {
  return stamp > 0.0 ? static_cast<std::uint64_t>(std::llround(stamp * 1e9)) : 0;
}

ros2::Header header(double stamp, std::string_view frame) {
  return {ros2::Time::from_nanoseconds(nanoseconds(stamp)), std::string(frame)};
}

ros2::TransformStamped transform(double stamp, std::string_view parent, std::string_view child,
                                 const Eigen::Isometry3d& parent_from_child) {
  return {header(stamp, parent), std::string(child), parent_from_child};
}

/// The scan's points in its sensor frame: x, y, z and, where the sensor says, the time (s from the stamp).
ros2::PointCloud2 point_cloud(const ScanEvent& scan) {
  const bool timed = scan.point_times.size() == scan.points.size() && !scan.points.empty();
  ros2::PointCloud2 cloud;
  cloud.header = header(scan.stamp, kSensorFrame);
  cloud.fields = {{"x", 0}, {"y", 4}, {"z", 8}};
  if (timed)
    cloud.fields.push_back({"time", 12});
  cloud.point_step = timed ? 16 : 12;
  cloud.width = static_cast<std::uint32_t>(scan.points.size());
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.resize(cloud.row_step);
  std::uint8_t* out = cloud.data.data();
  for (std::size_t i = 0; i < scan.points.size(); ++i, out += cloud.point_step) {
    std::memcpy(out, scan.points[i].data(), 12);
    if (timed)
      std::memcpy(out + 12, &scan.point_times[i], 4);
  }
  return cloud;
}

ros2::Odometry odometry(const RobotSample& sample) {
  ros2::Odometry message;
  message.header = header(sample.stamp, kOdomFrame);
  message.child_frame_id = kBaseFrame;
  message.pose.pose = sample.odometry.to_isometry();
  if (sample.velocity_known) {
    message.twist.twist.linear.x() = sample.velocity.v;
    message.twist.twist.angular.z() = sample.velocity.w;
  }
  return message;
}

/// The accelerometer's reading at rest (gravity, upwards in the base frame); no orientation, no rates.
ros2::Imu imu(double stamp, const GravityReading& gravity) {
  ros2::Imu message;
  message.header = header(stamp, kBaseFrame);
  message.orientation_covariance[0] = -1.0;
  message.angular_velocity_covariance[0] = -1.0;
  message.linear_acceleration = kStandardGravity * gravity.up_in_base;
  const double variance = std::pow(kStandardGravity * gravity.sigma, 2);
  for (int i = 0; i < 3; ++i)
    message.linear_acceleration_covariance[static_cast<std::size_t>(4 * i)] = variance;
  return message;
}

}  // namespace

fs::path McapRecordingWriter::partial_path(const fs::path& file) {
  return fs::path(file.string() + ".part");
}

McapRecordingWriter::McapRecordingWriter(fs::path file, const nlohmann::json& metadata,
                                         const Eigen::Isometry3d& initial_map_from_odom,
                                         mcap::Compression compression)
    : file_(std::move(file)), partial_(partial_path(file_)), writer_({.compression = compression}) {
  std::error_code error;
  if (fs::exists(file_, error))
    throw std::runtime_error(file_.string() + " exists (record into a new file)");
  out_.open(partial_, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw std::runtime_error("cannot write " + partial_.string());
  nlohmann::json recording = recording_metadata(metadata, initial_map_from_odom);
  recording["format"] = kMcapRecordingFormat;
  recording["version"] = kMcapRecordingVersion;
  recording["scans_csv_header"] = scans_csv_header();
  recording["odometry_csv_header"] = odometry_csv_header();
  write_row(kRecordingTopic, 0.0, recording.dump());
  writer_.close_chunk();
  write_out();
}

std::uint16_t McapRecordingWriter::channel(std::string_view topic, std::string_view type) {
  if (const auto found = channels_.find(topic); found != channels_.end())
    return found->second;
  auto schema = schemas_.find(type);
  if (schema == schemas_.end())
    schema =
        schemas_.emplace(type, writer_.add_schema(type, "ros2msg", ros2::ros2msg_definition(type))).first;
  const std::uint16_t id = writer_.add_channel(
      schema->second, topic, "cdr",
      topic == kMapTopic ? ros2::latched_channel_metadata() : std::map<std::string, std::string>{});
  channels_.emplace(topic, id);
  return id;
}

void McapRecordingWriter::add(std::string_view topic, std::string_view type, double stamp,
                              const std::vector<std::uint8_t>& cdr) {
  const std::uint16_t id = channel(topic, type);
  writer_.add_message(id, nanoseconds(stamp), nanoseconds(stamp), cdr);
}

void McapRecordingWriter::write_row(std::string_view topic, double stamp, std::string row) {
  if (!row.empty() && row.back() == '\n')
    row.pop_back();
  add(topic, ros2::String::kType, stamp, ros2::encode(ros2::String{std::move(row)}));
}

void McapRecordingWriter::write(const RobotSample& sample) {
  write_row(kOdometryRowsTopic, sample.stamp, odometry_csv_row(sample));
  add(kOdometryTopic, ros2::Odometry::kType, sample.stamp, ros2::encode(odometry(sample)));
  ros2::TFMessage tf;
  tf.transforms.push_back(transform(sample.stamp, kOdomFrame, kBaseFrame, sample.odometry.to_isometry()));
  add(kTfTopic, ros2::TFMessage::kType, sample.stamp, ros2::encode(tf));
  if (sample.gravity)
    add(kImuTopic, ros2::Imu::kType, sample.stamp, ros2::encode(imu(sample.stamp, *sample.gravity)));
  write_out();
}

void McapRecordingWriter::write(const ScanEvent& scan) {
  ros2::TFMessage tf;
  tf.transforms.push_back(transform(scan.stamp, kBaseFrame, kSensorFrame, scan.sensor_to_base));
  add(kTfTopic, ros2::TFMessage::kType, scan.stamp, ros2::encode(tf));
  add(kScanTopic, ros2::PointCloud2::kType, scan.stamp, ros2::encode(point_cloud(scan)));
  write_row(kScanRowsTopic, scan.stamp, scans_csv_row(scan, std::string(kScanTopic)));
  // Each scan closes its chunk: a killed run loses at most what came after the last scan.
  writer_.close_chunk();
  write_out();
}

void McapRecordingWriter::write(const TopicMessage& message) {
  add(message.topic, message.type, message.stamp, message.cdr);
  write_out();
}

void McapRecordingWriter::finish(const RecorderStatus& /*status*/) {
  writer_.finish();
  write_out();
  out_.close();
  if (!out_)
    throw std::runtime_error("cannot write " + partial_.string());
  std::error_code error;
  fs::rename(partial_, file_, error);
  if (error)
    throw std::runtime_error("cannot rename " + partial_.string() + " to " + file_.string() + ": " +
                             error.message());
}

void McapRecordingWriter::write_out() {
  const std::string bytes = writer_.take_output();
  if (bytes.empty())
    return;
  out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out_.flush();
  if (!out_)
    throw std::runtime_error("cannot write " + partial_.string());
}

}  // namespace strata::replay

#pragma once

#include <string_view>

namespace strata::replay {

// Strata's recording as an MCAP file of ROS 2 messages (`strata serve --record-mcap FILE`, docs/interop.md).
// What a replay reads, exactly as the own layout stores it (recording_layout.hpp), on std_msgs/String
// channels: /strata/recording (recording.json's content and the two CSV headers, first), /strata/scans (a
// scans.csv row per scan, its points the /scan message of the same sequence number) and
// /strata/odometry (an odometry.csv row per sample). Numbers in text with 17 digits are the doubles
// recorded, bit for bit; a quaternion is not. The rest is for viewers and ROS 2 tools.
inline constexpr std::string_view kRecordingTopic = "/strata/recording";
inline constexpr std::string_view kScanRowsTopic = "/strata/scans";
inline constexpr std::string_view kOdometryRowsTopic = "/strata/odometry";
inline constexpr std::string_view kScanTopic = "/scan";  ///< PointCloud2 in the sensor frame: x y z time
inline constexpr std::string_view kOdometryTopic = "/odom";
inline constexpr std::string_view kImuTopic = "/imu";
inline constexpr std::string_view kTfTopic = "/tf";
inline constexpr std::string_view kMapTopic = "/map";  ///< latched, as map_server's (offered_qos_profiles)
inline constexpr std::string_view kMcapRecordingFormat = "strata-recording-mcap";
inline constexpr int kMcapRecordingVersion = 1;

// Frames: map -> odom (the localizer's correction) -> base_link (the odometry) -> sensor (the mounting).
inline constexpr std::string_view kMapFrame = "map";
inline constexpr std::string_view kOdomFrame = "odom";
inline constexpr std::string_view kBaseFrame = "base_link";
inline constexpr std::string_view kSensorFrame = "sensor";

}  // namespace strata::replay

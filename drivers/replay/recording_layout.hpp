#pragma once

#include <string>
#include <string_view>

#include "drivers/robot_sample.hpp"
#include "drivers/scan_event.hpp"

namespace strata::replay {

// Strata's recording layout (what `strata serve --record DIR` writes and `--replay DIR` reads):
//   recording.json   what was recorded: format and version, source, seed, initial pose, counts
//   scans.csv        one row per scan, in order: its file, stamp, odometry, truth, mounting (header row
//   first) scans/NNNNNN.pcd the scan's points in its sensor frame, binary float32 PCD odometry.csv     every
//   odometry sample, in order (header row first)
// Numbers are written with 17 significant digits, so a replay reads back exactly the doubles recorded.
// A row is added to scans.csv only after its scan file is in place: a recording cut short by a crash is
// still a consistent, replayable prefix.

inline constexpr std::string_view kRecordingFile = "recording.json";
inline constexpr std::string_view kScansFile = "scans.csv";
inline constexpr std::string_view kOdometryFile = "odometry.csv";
inline constexpr std::string_view kScansDirectory = "scans";
inline constexpr std::string_view kRecordingFormat = "strata-recording";
inline constexpr int kRecordingVersion = 1;

/// The header of scans.csv: file, stamp, duration, sensor, rays, max_range, the odometry pose (x y z roll
/// pitch yaw), the true pose (truth_x ... truth_yaw, empty when unknown), the sensor's mounting (mount_00 ...
/// mount_23, 3x4 row-major).
[[nodiscard]] std::string scans_csv_header();
/// One row of scans.csv for `scan`, stored as `file` (relative to the recording).
[[nodiscard]] std::string scans_csv_row(const ScanEvent& scan, const std::string& file);
/// The header of odometry.csv: stamp, the odometry pose, the true pose.
[[nodiscard]] std::string odometry_csv_header();
[[nodiscard]] std::string odometry_csv_row(const RobotSample& sample);
/// scans/NNNNNN.pcd for the index-th scan (from 0).
[[nodiscard]] std::string scan_file_name(std::size_t index);

}  // namespace strata::replay

#include "drivers/replay/recording_layout.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

namespace strata::replay {
namespace {

constexpr const char* kPoseColumns = "x,y,z,roll,pitch,yaw";
constexpr const char* kTruthColumns = "truth_x,truth_y,truth_z,truth_roll,truth_pitch,truth_yaw";

std::string number(double value) {
  return fmt::format("{:.17g}", value);
}

std::string pose(const Pose3& pose) {
  return fmt::format("{},{},{},{},{},{}", number(pose.position.x()), number(pose.position.y()),
                     number(pose.position.z()), number(pose.roll), number(pose.pitch), number(pose.yaw));
}

}  // namespace

std::string scans_csv_header() {
  std::string header =
      fmt::format("file,stamp,duration,sensor,rays,max_range,{},{}", kPoseColumns, kTruthColumns);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col)
      header += fmt::format(",mount_{}{}", row, col);
  }
  return header + ",up_x,up_y,up_z,up_sigma,gyro_rate,gyro_seconds,gyro_sigma\n";
}

std::string scans_csv_row(const ScanEvent& scan, const std::string& file) {
  std::string sensor = scan.sensor;
  std::replace(sensor.begin(), sensor.end(), ',', '_');  // a CSV field
  // A lidar alone's scans have no odometry: empty fields, so that the replay predicts the motion from the
  // scans again rather than taking the constant pose for a robot standing still.
  std::string row = fmt::format("{},{},{},{},{},{},{},{}", file, number(scan.stamp), number(scan.duration),
                                sensor, scan.rays, number(scan.max_range),
                                scan.has_odometry ? pose(scan.odometry) : std::string(",,,,,"),
                                scan.truth ? pose(*scan.truth) : std::string(",,,,,"));
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c)
      row += "," + number(scan.sensor_to_base.matrix()(r, c));
  }
  // The IMU's gravity reading: empty fields without one.
  if (scan.gravity) {
    row += fmt::format(",{},{},{},{}", number(scan.gravity->up_in_base.x()),
                       number(scan.gravity->up_in_base.y()), number(scan.gravity->up_in_base.z()),
                       number(scan.gravity->sigma));
  } else {
    row += ",,,,";
  }
  // What the gyro read standing before the scan: empty fields without a stand.
  if (scan.standing_gyro) {
    row += fmt::format(",{},{},{}", number(scan.standing_gyro->rate), number(scan.standing_gyro->seconds),
                       number(scan.standing_gyro->sigma));
  } else {
    row += ",,,";
  }
  return row + "\n";
}

std::string odometry_csv_header() {
  return fmt::format("stamp,{},{}\n", kPoseColumns, kTruthColumns);
}

std::string odometry_csv_row(const RobotSample& sample) {
  return fmt::format("{},{},{}\n", number(sample.stamp), pose(sample.odometry),
                     sample.truth ? pose(*sample.truth) : std::string(",,,,,"));
}

std::string scan_file_name(std::size_t index) {
  return fmt::format("{}/{:06d}.pcd", kScansDirectory, index);
}

}  // namespace strata::replay

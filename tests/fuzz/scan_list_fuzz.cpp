// A replay's scan list, scans.csv (strata serve --replay DIR: a Strata recording's, or a hand-made list of
// point files with stamps, poses, mountings and IMU readings). The parser either refuses the text
// (DatasetError naming the line or the scan) or returns scans in time order with finite numbers, a unit
// gravity direction and usable gyro readings.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/replay/dataset.hpp"
#include "drivers/replay/scan_list.hpp"

namespace {

bool finite(const strata::Pose3& pose) {
  return pose.position.allFinite() && std::isfinite(pose.roll) && std::isfinite(pose.pitch) &&
         std::isfinite(pose.yaw);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream csv(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<strata::replay::DatasetScan> scans;
  try {
    scans = strata::replay::parse_scan_list(csv, "recording", "recording/scans.csv");
  } catch (const strata::replay::DatasetError&) {
    return 0;
  }
  if (scans.empty())
    __builtin_trap();  // a list without scans is refused
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const strata::replay::DatasetScan& scan = scans[i];
    if (!std::isfinite(scan.stamp) || (i > 0 && scan.stamp < scans[i - 1].stamp))
      __builtin_trap();
    if (!std::isfinite(scan.duration) || !std::isfinite(scan.max_range) ||
        !scan.sensor_to_base.matrix().allFinite())
      __builtin_trap();
    if ((scan.odometry && !finite(*scan.odometry)) || (scan.reference && !finite(*scan.reference)))
      __builtin_trap();
    if (scan.gravity &&
        !(std::abs(scan.gravity->up_in_base.norm() - 1.0) < 1e-6 && scan.gravity->sigma > 0.0))
      __builtin_trap();  // a unit direction, whatever length the file wrote
    if (scan.standing_gyro && !scan.standing_gyro->usable())
      __builtin_trap();
  }
  return 0;
}

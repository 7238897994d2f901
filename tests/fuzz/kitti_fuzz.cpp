// KITTI odometry datasets (strata serve --replay DIR): every input is read as each of the dataset's files,
// velodyne/NNNNNN.bin (float32 x y z reflectance records) and the text files poses.txt (12 numbers a line),
// times.txt (one a line) and calib.txt (a "Tr:" line). Each reader either refuses the text
// (PointFileError naming the line) or returns finite values.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/io/kitti_reader.hpp"
#include "drivers/io/point_file_error.hpp"

namespace {

std::vector<Eigen::Isometry3d> poses(const std::string& text) {
  std::istringstream in(text);
  try {
    std::vector<Eigen::Isometry3d> read = strata::io::read_kitti_poses(in, "poses.txt");
    for (const Eigen::Isometry3d& pose : read) {
      if (!pose.matrix().allFinite())
        __builtin_trap();
    }
    return read;
  } catch (const strata::io::PointFileError&) {
    return {};
  }
}

void times(const std::string& text) {
  std::istringstream in(text);
  try {
    for (const double time : strata::io::read_kitti_times(in, "times.txt")) {
      if (!std::isfinite(time))
        __builtin_trap();
    }
  } catch (const strata::io::PointFileError&) {
  }
}

std::optional<Eigen::Isometry3d> calibration(const std::string& text) {
  std::istringstream in(text);
  try {
    const std::optional<Eigen::Isometry3d> tr = strata::io::read_kitti_velodyne_to_camera(in, "calib.txt");
    if (tr && !tr->matrix().allFinite())
      __builtin_trap();
    return tr;
  } catch (const strata::io::PointFileError&) {
    return std::nullopt;
  }
}

void velodyne(std::string_view bytes) {
  try {
    const strata::io::LoadedCloud cloud = strata::io::parse_kitti_velodyne(bytes, "000000.bin");
    if (cloud.points.size() > bytes.size() / 16)
      __builtin_trap();
    for (const auto& point : cloud.points) {
      if (!point.allFinite())
        __builtin_trap();  // the reader drops non-finite points
    }
  } catch (const strata::io::PointFileError&) {
    if (bytes.size() % 16 == 0)
      __builtin_trap();  // only a size that is not whole records is refused
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::vector<Eigen::Isometry3d> camera_poses = poses(text);
  times(text);
  // The dataset's poses in the Velodyne's frame, with this calibration or the nominal mounting.
  static_cast<void>(strata::io::kitti_velodyne_poses(camera_poses, calibration(text)));
  velodyne(text);
  return 0;
}

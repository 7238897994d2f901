#include "drivers/io/kitti_reader.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "drivers/io/point_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {
namespace {

std::ifstream open(const std::filesystem::path& path, std::ios::openmode mode = std::ios::in) {
  std::ifstream in(path, mode);
  if (!in)
    throw PointFileError(path, "cannot open");
  return in;
}

/// Numbers of a line, or nothing when one of them is not a number.
std::optional<std::vector<double>> numbers(std::string_view line) {
  std::vector<double> values;
  for (const std::string_view field : split_fields(line)) {
    const auto value = parse_number(field);
    if (!value || !std::isfinite(*value))
      return std::nullopt;
    values.push_back(*value);
  }
  return values;
}

Eigen::Isometry3d from_row_major_3x4(const std::vector<double>& v) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col)
      m(row, col) = v[static_cast<std::size_t>(row * 4 + col)];
  }
  return Eigen::Isometry3d(m);
}

}  // namespace

LoadedCloud read_kitti_velodyne(const std::filesystem::path& path) {
  std::ifstream in = open(path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_kitti_velodyne(data, path);
}

LoadedCloud parse_kitti_velodyne(std::string_view bytes, const std::filesystem::path& source) {
  constexpr std::size_t kRecord = 4 * sizeof(float);
  if (bytes.size() % kRecord != 0) {
    throw PointFileError(source,
                         std::to_string(bytes.size()) +
                             " bytes is not a whole number of KITTI points (16 bytes: x y z reflectance)");
  }
  LoadedCloud cloud;
  cloud.points.reserve(bytes.size() / kRecord);
  for (std::size_t offset = 0; offset < bytes.size(); offset += kRecord) {
    float xyz[3];
    std::memcpy(xyz, bytes.data() + offset, sizeof xyz);  // little-endian, as KITTI wrote it and we run
    add_finite(cloud, Eigen::Vector3f(xyz[0], xyz[1], xyz[2]).cast<double>());
  }
  return cloud;
}

std::vector<Eigen::Isometry3d> read_kitti_poses(const std::filesystem::path& path) {
  std::ifstream in = open(path);
  return read_kitti_poses(in, path);
}

std::vector<Eigen::Isometry3d> read_kitti_poses(std::istream& in, const std::filesystem::path& source) {
  std::vector<Eigen::Isometry3d> poses;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (trimmed(line).empty())
      continue;
    const auto values = numbers(line);
    if (!values || values->size() != 12)
      throw PointFileError(source, "line " + std::to_string(number) + " is not 12 numbers (a 3x4 pose)");
    poses.push_back(from_row_major_3x4(*values));
  }
  return poses;
}

std::vector<double> read_kitti_times(const std::filesystem::path& path) {
  std::ifstream in = open(path);
  return read_kitti_times(in, path);
}

std::vector<double> read_kitti_times(std::istream& in, const std::filesystem::path& source) {
  std::vector<double> times;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (trimmed(line).empty())
      continue;
    const auto values = numbers(line);
    if (!values || values->size() != 1)
      throw PointFileError(source, "line " + std::to_string(number) + " is not one time in seconds");
    times.push_back(values->front());
  }
  return times;
}

std::optional<Eigen::Isometry3d> read_kitti_velodyne_to_camera(const std::filesystem::path& path) {
  std::ifstream in = open(path);
  return read_kitti_velodyne_to_camera(in, path);
}

std::optional<Eigen::Isometry3d> read_kitti_velodyne_to_camera(std::istream& in,
                                                               const std::filesystem::path& source) {
  std::string line;
  while (std::getline(in, line)) {
    const std::string_view text = trimmed(line);
    if (!text.starts_with("Tr:"))
      continue;
    const auto values = numbers(text.substr(3));
    if (!values || values->size() != 12)
      throw PointFileError(source, "Tr is not 12 numbers (a 3x4 transform)");
    return from_row_major_3x4(*values);
  }
  return std::nullopt;
}

std::vector<Eigen::Isometry3d> kitti_velodyne_poses(
    const std::vector<Eigen::Isometry3d>& camera_poses,
    const std::optional<Eigen::Isometry3d>& velodyne_to_camera) {
  Eigen::Isometry3d mounting = Eigen::Isometry3d::Identity();
  if (velodyne_to_camera) {
    mounting = *velodyne_to_camera;
  } else {
    // Camera axes (x right, y down, z forward) in terms of the Velodyne's (x forward, y left, z up).
    Eigen::Matrix3d rotation;
    rotation << 0, -1, 0, 0, 0, -1, 1, 0, 0;
    mounting.linear() = rotation;
  }
  // The Velodyne at scan i in camera 0's first frame is P_i * Tr; in the first Velodyne frame,
  // Tr^-1 * P_i * Tr.
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(camera_poses.size());
  for (const Eigen::Isometry3d& camera : camera_poses)
    poses.push_back(mounting.inverse() * camera * mounting);
  return poses;
}

}  // namespace strata::io

#include "drivers/io/threedtk_reader.hpp"

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "drivers/io/point_file_error.hpp"
#include "drivers/io/text_fields.hpp"

namespace strata::io {
namespace {

/// Strata axes from 3DTK axes: (x, y, z) = (z', -x', y').
Eigen::Matrix3d axis_change() {
  Eigen::Matrix3d c;
  c << 0, 0, 1, -1, 0, 0, 0, 1, 0;
  return c;
}

std::vector<double> numbers_of(std::string_view line) {
  std::vector<double> numbers;
  for (const std::string_view field : split_fields(line)) {
    const std::optional<double> value = parse_number(field);
    if (!value)
      return {};
    numbers.push_back(*value);
  }
  return numbers;
}

}  // namespace

Eigen::Isometry3d from_3dtk_frame(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation_cm) {
  const Eigen::Matrix3d c = axis_change();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = c * rotation * c.transpose();
  pose.translation() = c * translation_cm / 100.0;
  return pose;
}

LoadedCloud read_3dtk_scan(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw PointFileError(path, "cannot open");
  return read_3dtk_scan(in, path);
}

LoadedCloud read_3dtk_scan(std::istream& in, const std::filesystem::path& path) {
  const Eigen::Matrix3d c = axis_change();
  LoadedCloud cloud;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.empty())
      continue;
    if (line_number == 1 && fields.size() == 3 && fields[1] == "x")
      continue;  // legacy "360 x 225" header of pre-2019 files
    if (fields.size() < 3)
      throw PointFileError(path,
                           "line " + std::to_string(line_number) + ": expected 'x y z', got '" + line + "'");
    Eigen::Vector3d p;
    for (int axis = 0; axis < 3; ++axis) {
      const std::optional<double> value = parse_number(fields[static_cast<std::size_t>(axis)]);
      if (!value)
        throw PointFileError(path, "line " + std::to_string(line_number) + ": '" +
                                       std::string(fields[static_cast<std::size_t>(axis)]) +
                                       "' is not a number");
      p[axis] = *value;
    }
    if (p.allFinite() && p.norm() >= kThreeDtkMaxRangeCm)
      continue;
    add_finite(cloud, c * p / 100.0);
  }
  if (in.bad())
    throw PointFileError(path, "read error");
  return cloud;
}

Eigen::Isometry3d read_3dtk_pose(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw PointFileError(path, "cannot open");
  return read_3dtk_pose(in, path);
}

Eigen::Isometry3d read_3dtk_pose(std::istream& in, const std::filesystem::path& path) {
  std::string position_line;
  std::string angle_line;
  std::getline(in, position_line);
  std::getline(in, angle_line);
  const std::vector<double> t = numbers_of(position_line);
  const std::vector<double> a = numbers_of(angle_line);
  if (t.size() != 3 || a.size() != 3)
    throw PointFileError(path, "a .pose file needs two lines of three numbers: 'x y z' and 'rx ry rz'");
  const double to_radians = std::acos(-1.0) / 180.0;
  const double sx = std::sin(a[0] * to_radians), cx = std::cos(a[0] * to_radians);
  const double sy = std::sin(a[1] * to_radians), cy = std::cos(a[1] * to_radians);
  const double sz = std::sin(a[2] * to_radians), cz = std::cos(a[2] * to_radians);
  Eigen::Matrix3d r;                                              // 3DTK EulerToMatrix4, row-major
  r << cy * cz, -cy * sz, sy,                                     //
      sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy,  //
      -cx * sy * cz + sx * sz, cx * sy * sz + sx * cz, cx * cy;
  return from_3dtk_frame(r, {t[0], t[1], t[2]});
}

Eigen::Isometry3d read_3dtk_frames(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw PointFileError(path, "cannot open");
  return read_3dtk_frames(in, path);
}

Eigen::Isometry3d read_3dtk_frames(std::istream& in, const std::filesystem::path& path) {
  std::vector<double> last;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> numbers = numbers_of(line);
    if (numbers.size() == 16)
      last = std::move(numbers);
  }
  if (last.empty())
    throw PointFileError(path, "no line of 16 numbers (a 4x4 pose) in this .frames file");
  const Eigen::Map<const Eigen::Matrix4d> m(last.data());  // column-major, as OpenGL stores it
  return from_3dtk_frame(m.topLeftCorner<3, 3>(), m.topRightCorner<3, 1>());
}

}  // namespace strata::io

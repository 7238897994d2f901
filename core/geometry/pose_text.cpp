#include "core/geometry/pose_text.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace strata {

std::vector<double> parse_number_list(std::string_view text) {
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item(text.substr(start, comma == std::string_view::npos ? text.npos : comma - start));
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(value))
      throw std::invalid_argument("'" + item + "' is not a number");
    values.push_back(value);
    if (comma == std::string_view::npos)
      break;
    start = comma + 1;
  }
  return values;
}

Pose3 parse_pose_text(std::string_view text) {
  std::vector<double> values = parse_number_list(text);
  if (values.size() != 3 && values.size() != 6)
    throw std::invalid_argument("expected x,y,z or x,y,z,roll,pitch,yaw (metres, degrees)");
  values.resize(6, 0.0);
  constexpr double kRadians = std::numbers::pi / 180.0;
  Pose3 pose;
  pose.position = {values[0], values[1], values[2]};
  pose.roll = values[3] * kRadians;
  pose.pitch = values[4] * kRadians;
  pose.yaw = values[5] * kRadians;
  return pose;
}

Eigen::Vector3d parse_point_text(std::string_view text) {
  const std::vector<double> values = parse_number_list(text);
  if (values.size() != 3)
    throw std::invalid_argument("expected x,y,z (metres)");
  return {values[0], values[1], values[2]};
}

}  // namespace strata

#pragma once

#include <optional>

namespace strata {

/// Where an operator says the robot is (Set pose), map frame: a hint the localizer searches around.
struct PoseEstimate {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;         ///< radians, counter-clockwise from +x
  std::optional<double> z;  ///< the level; none: the level the map's robot drove at (x, y)
};

}  // namespace strata

#pragma once

#include <string_view>
#include <vector>

#include "core/geometry/pose.hpp"

namespace strata {

/// The command line's one pose syntax: "x,y,z" or "x,y,z,roll,pitch,yaw", metres and degrees (what a person
/// measures with a tape and reads off a protractor). Throws std::invalid_argument saying what is wrong: a
/// value that is not a finite number, or not 3 or 6 of them.
[[nodiscard]] Pose3 parse_pose_text(std::string_view text);

/// The comma-separated numbers of `text` ("1.5, -2,0"), each finite: what the command line's poses,
/// points and number pairs are written in. Throws std::invalid_argument naming the first item that is not
/// a number.
[[nodiscard]] std::vector<double> parse_number_list(std::string_view text);

/// A point in the same syntax: "x,y,z" in metres. Throws std::invalid_argument as parse_pose_text does.
[[nodiscard]] Eigen::Vector3d parse_point_text(std::string_view text);

}  // namespace strata

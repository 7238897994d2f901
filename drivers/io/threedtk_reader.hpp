#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <istream>

#include "drivers/io/loaded_cloud.hpp"

namespace strata::io {

// 3DTK (slam6D) files use centimetres and a LEFT-handed frame: x right, y up, z forward. Strata uses
// metres and the right-handed x forward, y left, z up. The conversion (as 3DTK's own ROS wrapper does) is
//   x = z_3dtk / 100,  y = -x_3dtk / 100,  z = y_3dtk / 100.
// It is a reflection, so a 3DTK pose (R, t) becomes (C R C^T, C t / 100) with C the axis permutation above:
// a proper rotation again.

/// Maximum-range readings of the 3DTK example scans' sensor (|p| ~ 3276 cm): no surface, so dropped (3DTK's
/// own viewer shows only |p| < 3276 cm).
inline constexpr double kThreeDtkMaxRangeCm = 3276.0;

/// Reads a 3DTK `.3d` scan ("x y z" per line, centimetres; extra columns ignored; the legacy first line
/// "W x H" skipped), converted to metres in Strata's frame. Max-range and non-finite readings are dropped
/// (counted in dropped_non_finite only for the non-finite ones). Throws PointFileError.
[[nodiscard]] LoadedCloud read_3dtk_scan(const std::filesystem::path& path);
/// The same from a stream; `source` names it in error messages.
[[nodiscard]] LoadedCloud read_3dtk_scan(std::istream& in, const std::filesystem::path& source);

/// Reads a 3DTK `.pose` file ("x y z" in cm, then "theta_x theta_y theta_z" in degrees, 3DTK's
/// EulerToMatrix4 convention): the scan's pose p_world = R p_scan + t, converted to Strata's frame.
[[nodiscard]] Eigen::Isometry3d read_3dtk_pose(const std::filesystem::path& path);
[[nodiscard]] Eigen::Isometry3d read_3dtk_pose(std::istream& in, const std::filesystem::path& source);

/// Reads a slam6D `.frames` file: the last line of 16 numbers (an OpenGL column-major 4x4, cm) is the
/// scan's final registered pose, converted to Strata's frame.
[[nodiscard]] Eigen::Isometry3d read_3dtk_frames(const std::filesystem::path& path);
[[nodiscard]] Eigen::Isometry3d read_3dtk_frames(std::istream& in, const std::filesystem::path& source);

/// A pose given in 3DTK's frame and units, converted to Strata's.
[[nodiscard]] Eigen::Isometry3d from_3dtk_frame(const Eigen::Matrix3d& rotation,
                                                const Eigen::Vector3d& translation_cm);

}  // namespace strata::io

#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace strata {

/// Where to look for the ground in a scan, in the sensor's frame (its z roughly up).
struct GroundPlaneOptions {
  double min_range = 1.0;         ///< m, horizontal: nearer points are the robot or whoever carries it
  double max_range = 30.0;        ///< m, horizontal: further, a sensor's slight tilt is metres of height
  double min_depth = 0.2;         ///< m below the sensor: the ground is under it
  double max_tilt_deg = 30.0;     ///< the ground's normal within this of the sensor's z axis
  double inlier_distance = 0.08;  ///< m from the plane: rings of a real sensor at 10-30 m scatter a few cm
  double thinning_voxel = 0.2;    ///< m: candidates thinned so that near rings do not outvote far ground
  std::size_t min_inliers = 100;  ///< thinned points on the plane
  int iterations = 300;           ///< RANSAC tries (seeded: the same scan gives the same plane)
};

/// The ground under a sensor: a plane in the sensor's frame, n . p + d = 0 with n pointing up to the sensor.
struct GroundPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, in the sensor frame, toward the sensor
  double height = 0.0;                                ///< m: the sensor's distance from the plane
  std::size_t inliers = 0;                            ///< thinned points within inlier_distance
  std::size_t candidates = 0;
  /// The sensor's pose on a base standing on this ground: the base's origin on the ground right below the
  /// sensor, its z the plane's normal, its x the sensor's x laid onto the plane (the sensor's heading is
  /// the base's: nothing in a scan tells them apart).
  [[nodiscard]] Eigen::Isometry3d sensor_to_base() const;
  /// The sensor's roll and pitch against the ground, degrees, for the log.
  [[nodiscard]] Eigen::Vector2d tilt_deg() const;
};

/// The largest plane under the sensor, nearly level in its frame (RANSAC over thinned points, refined by a
/// least-squares fit to its inliers), or nothing when no such plane holds `min_inliers` points: `why` then
/// says what was missing.
[[nodiscard]] std::optional<GroundPlane> find_ground_plane(const std::vector<Eigen::Vector3f>& points,
                                                           const GroundPlaneOptions& options = {},
                                                           std::string* why = nullptr);

}  // namespace strata

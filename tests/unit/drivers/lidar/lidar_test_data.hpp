#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

// Where the shared lidar captures are (../shared/data/lidar_pcap, or $STRATA_DATA_DIR/lidar_pcap), and
// geometry summaries the capture tests check.
namespace strata::lidar::test {

inline std::filesystem::path lidar_data_dir() {
  const char* from_env = std::getenv("STRATA_DATA_DIR");
  return (from_env != nullptr ? std::filesystem::path(from_env) : std::filesystem::path(STRATA_DATA_DIR)) /
         "lidar_pcap";
}

#define STRATA_SKIP_WITHOUT(file)                                     \
  if (!std::filesystem::exists(file))                                 \
  GTEST_SKIP() << "lidar capture " << (file)                          \
               << " not found (set STRATA_DATA_DIR to the directory " \
                  "holding lidar_pcap/)"

inline double median(std::vector<double> values) {
  if (values.empty())
    return 0.0;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2),
                   values.end());
  return values[values.size() / 2];
}

/// How many of 36 ten-degree azimuth sectors hold returns.
inline int azimuth_sectors_covered(const std::vector<Eigen::Vector3f>& points) {
  std::vector<bool> covered(36, false);
  for (const Eigen::Vector3f& p : points) {
    const double degrees =
        std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x())) * 180.0 / M_PI + 180.0;
    covered[std::min(35, static_cast<int>(degrees / 10.0))] = true;
  }
  return static_cast<int>(std::count(covered.begin(), covered.end(), true));
}

/// The ground as the decoded geometry shows it: in each 10 degree azimuth sector with enough returns,
/// the mean of its lowest 5 % of points; a plane fitted to those. A correct decoding of a sensor above
/// a floor or road gives a near-horizontal plane below the sensor; a mis-signed elevation, swapped axes
/// or wrong angle units do not.
struct Ground {
  double height = 0.0;    ///< m, the plane's z under the sensor
  double normal_z = 0.0;  ///< upward component of its unit normal
  double rms = 0.0;       ///< m, residual of the sector points
  int sectors = 0;        ///< sectors that contributed
};
inline Ground find_ground(const std::vector<Eigen::Vector3f>& points) {
  std::vector<std::vector<Eigen::Vector3d>> sectors(36);
  for (const Eigen::Vector3f& p : points) {
    const double degrees =
        std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x())) * 180.0 / M_PI + 180.0;
    sectors[static_cast<std::size_t>(std::min(35, static_cast<int>(degrees / 10.0)))].push_back(
        p.cast<double>());
  }
  std::vector<Eigen::Vector3d> lowest;
  for (std::vector<Eigen::Vector3d>& sector : sectors) {
    if (sector.size() < 100)
      continue;
    std::sort(sector.begin(), sector.end(),
              [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.z() < b.z(); });
    const std::size_t count = sector.size() / 20;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < count; ++i)
      sum += sector[i];
    lowest.push_back(sum / static_cast<double>(count));
  }
  Ground ground;
  ground.sectors = static_cast<int>(lowest.size());
  if (lowest.size() < 3)
    return ground;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : lowest)
    mean += p;
  mean /= static_cast<double>(lowest.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : lowest)
    scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Vector3d normal = solver.eigenvectors().col(0);  // smallest eigenvalue first
  if (normal.z() < 0.0)
    normal = -normal;
  ground.normal_z = normal.z();
  ground.height = normal.dot(mean) / normal.z();
  ground.rms = std::sqrt(solver.eigenvalues()(0) / static_cast<double>(lowest.size()));
  return ground;
}

/// Fraction of points farther than `range` m from the sensor.
inline double fraction_beyond(const std::vector<Eigen::Vector3f>& points, double range) {
  const auto beyond = std::count_if(points.begin(), points.end(), [&](const Eigen::Vector3f& p) {
    return static_cast<double>(p.norm()) > range;
  });
  return points.empty() ? 0.0 : static_cast<double>(beyond) / static_cast<double>(points.size());
}

/// What a correct decoding of a real capture looks like: ranges within the datasheet's (a few returns from
/// retro-reflectors beyond it), a median range for the scene, returns all around, and the ground a
/// near-horizontal plane 0.3-3 m below the sensor.
inline void expect_plausible_geometry(const std::vector<Eigen::Vector3f>& points, const std::string& what,
                                      double spec_range, double median_low, double median_high) {
  std::vector<double> ranges;
  for (const Eigen::Vector3f& p : points)
    ranges.push_back(static_cast<double>(p.norm()));
  ASSERT_GT(ranges.size(), 10000u) << what;
  const double max_range = *std::max_element(ranges.begin(), ranges.end());
  const double beyond = fraction_beyond(points, spec_range);
  const Ground ground = find_ground(points);
  std::printf(
      "%s: %zu returns, median range %.2f m, max %.2f m (%.4f %% beyond %.0f m), ground plane z %.2f m, "
      "normal z %.3f, rms %.3f m over %d sectors\n",
      what.c_str(), points.size(), median(ranges), max_range, 100.0 * beyond, spec_range, ground.height,
      ground.normal_z, ground.rms, ground.sectors);
  EXPECT_LT(beyond, 0.001) << what;
  EXPECT_LT(max_range, 1.5 * spec_range) << what;
  EXPECT_GT(*std::min_element(ranges.begin(), ranges.end()), 0.0) << what;
  EXPECT_GT(median(ranges), median_low) << what;
  EXPECT_LT(median(ranges), median_high) << what;
  EXPECT_GE(azimuth_sectors_covered(points), 34) << what;
  EXPECT_GE(ground.sectors, 30) << what;
  EXPECT_GT(ground.normal_z, 0.95) << what;
  EXPECT_LT(ground.height, -0.3) << what;
  EXPECT_GT(ground.height, -3.0) << what;
  EXPECT_LT(ground.rms, 0.5) << what;  // outdoor captures have kerbs, slopes, vegetation
}

}  // namespace strata::lidar::test

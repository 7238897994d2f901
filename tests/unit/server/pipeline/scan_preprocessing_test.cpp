#include "server/pipeline/scan_preprocessing.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace strata::pipeline {
namespace {

TEST(ScanPreprocessing, CleansAndMovesPointsIntoTheBaseFrame) {
  ScanEvent scan;
  scan.max_range = 8.1;
  scan.sensor_to_base.translation() = Eigen::Vector3d(0.2, 0, 1.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  scan.points = {
      {2, 0, 0},     // kept
      {0.1f, 0, 0},  // the robot itself: too close
      {8.1f, 0, 0},  // a max-range "no return"
      {nan, 0, 0},   // invalid
      {0, 3, -1},    // kept
      {std::numeric_limits<float>::infinity(), 0, 0},
  };
  const PointCloud points = points_in_base(scan);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_TRUE(points[0].isApprox(Eigen::Vector3d(2.2, 0, 1.0)));
  EXPECT_TRUE(points[1].isApprox(Eigen::Vector3d(0.2, 3, 0.0)));
}

TEST(ScanPreprocessing, SensorsWithoutMaxRangeReadingsKeepFarPoints) {
  ScanEvent scan;  // max_range 0: the sensor drops no-returns itself
  scan.points = {{80, 0, 0}};
  EXPECT_EQ(points_in_base(scan).size(), 1u);
}

}  // namespace
}  // namespace strata::pipeline

#include "server/pipeline/scan_preprocessing.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

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

TEST(ScanPreprocessing, ThePointsTimesAreKeptWithThePointsKept) {
  ScanEvent scan;
  scan.points = {{2, 0, 0}, {0.1f, 0, 0}, {0, 3, 0}};
  scan.point_times = {-0.09f, -0.05f, -0.01f};
  std::vector<float> times;
  EXPECT_EQ(points_in_base(scan, 0.3, &times).size(), 2u);
  EXPECT_EQ(times, (std::vector<float>{-0.09f, -0.01f}));
  const PreprocessedScan preprocessed = preprocess(scan);
  EXPECT_EQ(preprocessed.times, times);
  EXPECT_TRUE(preprocessed.event.point_times.empty());  // released with the raw points
  scan.point_times.pop_back();                          // not one per point: unknown
  EXPECT_EQ(points_in_base(scan, 0.3, &times).size(), 2u);
  EXPECT_TRUE(times.empty());
}

TEST(ScanPreprocessing, SensorsWithoutMaxRangeReadingsKeepFarPoints) {
  ScanEvent scan;  // max_range 0: the sensor drops no-returns itself
  scan.points = {{80, 0, 0}};
  EXPECT_EQ(points_in_base(scan).size(), 1u);
}

}  // namespace
}  // namespace strata::pipeline

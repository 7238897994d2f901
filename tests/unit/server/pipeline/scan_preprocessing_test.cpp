#include "server/pipeline/scan_preprocessing.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace strata::pipeline {
namespace {

TEST(ScanPreprocessing, CleansWithTheScansOwnMountingAndNoReturnRange) {
  ScanEvent scan;
  scan.max_range = 8.1;
  scan.sensor_to_base.translation() = Eigen::Vector3d(0.2, 0, 1.0);
  scan.points = {{2, 0, 0}, {0.1f, 0, 0}, {8.1f, 0, 0}};
  const PointCloud points = points_in_base(scan);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_TRUE(points[0].isApprox(Eigen::Vector3d(2.2, 0, 1.0)));
}

TEST(ScanPreprocessing, KeepsThePointsTimesAndReleasesTheRawScan) {
  ScanEvent scan;
  scan.points = {{2, 0, 0}, {0.1f, 0, 0}, {0, 3, 0}};
  scan.point_times = {-0.09f, -0.05f, -0.01f};
  const PreprocessedScan preprocessed = preprocess(scan);
  EXPECT_EQ(preprocessed.points.size(), 2u);
  EXPECT_EQ(preprocessed.times, (std::vector<float>{-0.09f, -0.01f}));
  EXPECT_TRUE(preprocessed.event.points.empty());  // released
  EXPECT_TRUE(preprocessed.event.point_times.empty());
}

}  // namespace
}  // namespace strata::pipeline

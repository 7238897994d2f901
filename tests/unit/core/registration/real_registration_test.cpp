// Registration on the real pairs in STRATA_DATA_DIR (skipped when absent). Tolerances are generous but
// meaningful: each asks for a result clearly better than the starting guess and near the published one.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/registration/register_scan.hpp"
#include "drivers/io/point_cloud_file.hpp"
#include "drivers/io/threedtk_reader.hpp"
#include "tests/support/synthetic_scenes.hpp"

namespace strata {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

fs::path data_dir() {
  const char* from_env = std::getenv("STRATA_DATA_DIR");
  return from_env != nullptr ? fs::path(from_env) : fs::path(STRATA_DATA_DIR);
}

#define SKIP_WITHOUT(path) \
  if (!fs::exists(path))   \
  GTEST_SKIP() << "real data not found at " << (path) << " (set STRATA_DATA_DIR to the shared data folder)"

TEST(RealData, ThreeDtkScan1OntoScan0FromOdometry) {
  const fs::path dir = data_dir() / "3dtk_dat";
  SKIP_WITHOUT(dir / "scan001.3d");
  const io::LoadedCloud scan0 = io::read_point_cloud(dir / "scan000.3d");
  const io::LoadedCloud scan1 = io::read_point_cloud(dir / "scan001.3d");
  EXPECT_GT(scan0.points.size(), 79000U);  // 81360 minus the max-range readings
  for (const Eigen::Vector3d& p : scan0.points)
    ASSERT_LT(p.norm(), 32.76);
  const Eigen::Isometry3d odometry =
      io::read_3dtk_pose(dir / "scan000.pose").inverse() * io::read_3dtk_pose(dir / "scan001.pose");
  const Eigen::Isometry3d reference =
      io::read_3dtk_frames(dir / "reference_slam6d_2009/scan000.frames").inverse() *
      io::read_3dtk_frames(dir / "reference_slam6d_2009/scan001.frames");
  // Sanity of the frame conversion: the robot drove ~1.5 m forward (+x), odometry within 10 cm of the
  // reference.
  EXPECT_NEAR(reference.translation().x(), 1.53, 0.05);
  EXPECT_LT(test::translation_error(odometry, reference), 0.10);
  const RegistrationResult result = register_scan(scan1.points, scan0.points, odometry);
  EXPECT_TRUE(result.accepted()) << result.assessment.message;
  EXPECT_LT(test::translation_error(result.transform, reference), 0.05);
  EXPECT_LT(test::rotation_error(result.transform, reference), 0.4 * kDeg);
  EXPECT_LT(result.rmse, 0.15);
}

TEST(RealData, LibpointmatcherCarFromIdentity) {
  const fs::path dir = data_dir() / "pairs/libpointmatcher_car";
  SKIP_WITHOUT(dir / "car_cloud400.csv");
  const io::LoadedCloud target = io::read_point_cloud(dir / "car_cloud400.csv");
  const io::LoadedCloud source = io::read_point_cloud(dir / "car_cloud401.csv");
  EXPECT_EQ(target.points.size(), 24989U);
  EXPECT_EQ(source.points.size(), 25193U);
  Eigen::Matrix4d g;
  g << 0.981715, 0.169605, -0.0864239, 0.0614127, -0.152902, 0.973034, 0.172703, 0.191433, 0.113385, -0.15633,
      0.981175, -0.0338571, 0, 0, 0, 1;  // carCloudList.csv
  const Eigen::Isometry3d reference(g);
  const RegistrationResult result =
      register_scan(source.points, target.points, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(result.accepted()) << result.assessment.message;
  EXPECT_LT(test::translation_error(result.transform, reference), 0.05);
  EXPECT_LT(test::rotation_error(result.transform, reference), 0.5 * kDeg);
}

TEST(RealData, PclRoomConvergesFromTheTutorialGuess) {
  const fs::path dir = data_dir() / "pairs/pcl_room";
  SKIP_WITHOUT(dir / "room_scan1.pcd");
  const io::LoadedCloud target = io::read_point_cloud(dir / "room_scan1.pcd");
  const io::LoadedCloud source = io::read_point_cloud(dir / "room_scan2.pcd");
  EXPECT_EQ(target.points.size() + target.dropped_non_finite, 112586U);
  EXPECT_EQ(source.points.size() + source.dropped_non_finite, 112624U);
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  guess.translate(Eigen::Vector3d(1.79387, 0.720047, 0.0));
  guess.rotate(Eigen::AngleAxisd(0.6931, Eigen::Vector3d::UnitZ()));
  const RegistrationResult result = register_scan(source.points, target.points, guess);
  EXPECT_TRUE(result.accepted()) << result.assessment.message;
  // The README's independent ICP: yaw 40.8 deg, t = (1.975, 0.059, 0.027); the guess is 0.69 m away.
  EXPECT_NEAR(result.transform.translation().x(), 1.975, 0.05);
  EXPECT_NEAR(result.transform.translation().y(), 0.059, 0.05);
  EXPECT_NEAR(Eigen::AngleAxisd(result.transform.rotation()).angle(), 40.8 * kDeg, 0.5 * kDeg);
}

}  // namespace
}  // namespace strata

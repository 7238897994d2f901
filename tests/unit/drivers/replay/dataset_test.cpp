// The replay's dataset layouts: recognising them, reading their indexes and points, and clear errors for
// what is missing or broken (issue #9 item 1).
#include "drivers/replay/dataset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "drivers/io/pcd_reader.hpp"
#include "drivers/io/pcd_writer.hpp"

namespace strata::replay {
namespace {

namespace fs = std::filesystem;

class Datasets : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("strata_datasets_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path path = dir_ / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  static std::string kitti_bin(const std::vector<Eigen::Vector3f>& points) {
    std::string bytes;
    for (const auto& p : points) {
      const float record[4] = {p.x(), p.y(), p.z(), 0.5f};
      bytes.append(reinterpret_cast<const char*>(record), sizeof record);
    }
    return bytes;
  }

  /// The error open_dataset throws for dir_ (fails the test if it throws none).
  std::string open_error() {
    try {
      (void)open_dataset(dir_);
    } catch (const DatasetError& error) {
      return error.what();
    }
    ADD_FAILURE() << "no error";
    return {};
  }

  fs::path dir_;
};

const std::vector<Eigen::Vector3f> kPoints{{1.0f, 2.0f, 3.0f}, {-0.125f, 4.5f, 1e-3f}, {7.0f, -8.0f, 0.25f}};

TEST(PcdWriter, BinaryPcdReadsBackBitForBit) {
  const fs::path path = fs::temp_directory_path() / "strata_pcd_writer_test.pcd";
  std::ofstream(path, std::ios::binary) << io::encode_binary_pcd(kPoints);
  const auto cloud = io::read_pcd(path);
  fs::remove(path);
  ASSERT_EQ(cloud.points.size(), kPoints.size());
  for (std::size_t i = 0; i < kPoints.size(); ++i)
    EXPECT_EQ(cloud.points[i].cast<float>(), kPoints[i]) << i;
}

TEST_F(Datasets, KittiVelodyneWithPosesAndTimes) {
  write("velodyne/000000.bin", kitti_bin(kPoints));
  write("velodyne/000001.bin", kitti_bin({{5.0f, 0.0f, 0.0f}}));
  // Camera 0 (z forward) moves 2 m forward and turns 90 degrees left (about -y, camera y is down).
  write("poses.txt",
        "1 0 0 0 0 1 0 0 0 0 1 0\n"
        "0 0 -1 0 0 1 0 0 1 0 0 2\n");
  write("times.txt", "0.0\n0.1036\n");
  const Dataset dataset = open_dataset(dir_);
  EXPECT_EQ(dataset.layout, DatasetLayout::kKitti);
  ASSERT_EQ(dataset.scans.size(), 2u);
  EXPECT_DOUBLE_EQ(dataset.scans[1].stamp, 0.1036);
  EXPECT_FALSE(dataset.scans[0].odometry.has_value());  // KITTI has ground truth, no odometry
  ASSERT_TRUE(dataset.scans[1].reference.has_value());
  // In the Velodyne's frame (x forward, y left): 2 m along x, heading +90 degrees.
  const Pose3& second = *dataset.scans[1].reference;
  EXPECT_NEAR(second.position.x(), 2.0, 1e-12);
  EXPECT_NEAR(second.position.y(), 0.0, 1e-12);
  EXPECT_NEAR(second.yaw, M_PI / 2, 1e-12);
  EXPECT_EQ(load_points(dataset.scans[0]), kPoints);
}

TEST_F(Datasets, KittiWithoutPosesOrWithTooFewIsAClearError) {
  write("velodyne/000000.bin", kitti_bin(kPoints));
  write("velodyne/000001.bin", kitti_bin(kPoints));
  EXPECT_NE(open_error().find("without poses.txt"), std::string::npos);
  write("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_NE(open_error().find("1 poses for 2 velodyne scans"), std::string::npos);
  write("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_NE(open_error().find("line 2 is not 12 numbers"), std::string::npos);
}

TEST_F(Datasets, CorruptKittiScanIsAClearErrorWhenPlayed) {
  write("velodyne/000000.bin", kitti_bin(kPoints) + "x");
  write("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
  const Dataset dataset = open_dataset(dir_);
  try {
    (void)load_points(dataset.scans[0]);
    FAIL() << "no error";
  } catch (const DatasetError& error) {
    EXPECT_NE(std::string(error.what()).find("not a whole number of KITTI points"), std::string::npos);
  }
}

TEST_F(Datasets, ThreeDtkScanWithoutPoseIsAClearError) {
  write("scan000.3d", "0 0 100\n");
  write("scan000.pose", "0 0 0\n0 0 0\n");
  write("scan001.3d", "0 0 100\n");
  EXPECT_NE(open_error().find("scan001.3d has no odometry pose scan001.pose"), std::string::npos);
}

TEST_F(Datasets, ThreeDtkExampleScansWithReferencePoses) {
  const fs::path data = fs::path(STRATA_DATA_DIR) / "3dtk_dat";
  if (!fs::exists(data / "scan000.3d"))
    GTEST_SKIP() << "no 3DTK example data at " << data << " (set STRATA_DATA_DIR)";
  const Dataset dataset = open_dataset(data);
  EXPECT_EQ(dataset.layout, DatasetLayout::kThreeDtk);
  ASSERT_EQ(dataset.scans.size(), 3u);
  for (const auto& scan : dataset.scans) {
    ASSERT_TRUE(scan.odometry.has_value());
    ASSERT_TRUE(scan.reference.has_value());  // reference_slam6d_2009/*.frames
  }
  // README.txt: scan002 is 3.33 m ahead (3DTK z forward is Strata's x); odometry within 7 cm of it.
  EXPECT_NEAR(dataset.scans[2].reference->position.x(), 3.325, 0.01);
  EXPECT_LT((dataset.scans[2].odometry->position - dataset.scans[2].reference->position).norm(), 0.1);
  EXPECT_GT(load_points(dataset.scans[0]).size(), 70000u);
}

TEST_F(Datasets, ScanListOfPointFiles) {
  write("a.pcd", io::encode_binary_pcd(kPoints));
  write("b.pcd", io::encode_binary_pcd(kPoints));
  write("scans.csv", "file,stamp,x,y,z,roll,pitch,yaw\na.pcd,0,0,0,0,0,0,0\nb.pcd,1.5,1,2,0,0,0,0.5\n");
  const Dataset dataset = open_dataset(dir_);
  EXPECT_EQ(dataset.layout, DatasetLayout::kScanList);
  ASSERT_EQ(dataset.scans.size(), 2u);
  EXPECT_EQ(dataset.scans[1].odometry->position, Eigen::Vector3d(1, 2, 0));
  EXPECT_EQ(dataset.scans[1].odometry->yaw, 0.5);
  EXPECT_FALSE(dataset.scans[1].reference.has_value());
  EXPECT_EQ(load_points(dataset.scans[1]), kPoints);
}

TEST_F(Datasets, ScanListErrorsNameTheLine) {
  write("a.pcd", io::encode_binary_pcd(kPoints));
  write("scans.csv", "file,stamp,x,y,z,roll,pitch,yaw\na.pcd,0,0,0,zero,0,0,0\n");
  EXPECT_NE(open_error().find("line 2: z 'zero' is not a number"), std::string::npos);
  write("scans.csv", "file,stamp\na.pcd,0\nmissing.pcd,1\n");
  EXPECT_NE(open_error().find("missing.pcd does not exist"), std::string::npos);
  write("scans.csv",
        "file,stamp,rays\na.pcd,0,1e300\n");  // an undefined conversion (found by the fuzz target)
  EXPECT_NE(open_error().find("scan 0: 1e+300 rays is beyond any scan's (1e+09)"), std::string::npos);
  write("scans.csv", "file,stamp\na.pcd,0,7\n");
  EXPECT_NE(open_error().find("line 2 has 3 fields, the header 2"), std::string::npos);
  write("scans.csv", "file,stamp,up_x,up_y,up_z,up_sigma\na.pcd,0,0,0,0,0.01\n");
  EXPECT_NE(open_error().find("gravity reading (0, 0, 0; sigma 0.01) is not a direction"), std::string::npos);
  write("scans.csv", "file,stamp,up_x,up_y,up_z,up_sigma\na.pcd,0,0,0,1,-1\n");
  EXPECT_NE(open_error().find("with a positive sigma"), std::string::npos);
  write("scans.csv", "file,stamp,gyro_rate,gyro_seconds,gyro_sigma\na.pcd,0,1e-4,0,1e-5\n");
  EXPECT_NE(open_error().find("scan 0: the standing gyro reading (0.0001 rad/s over 0 s; sigma 1e-05) needs"),
            std::string::npos);
  write("scans.csv", "file,stamp,gyro_rate,gyro_seconds,gyro_sigma\na.pcd,0,nan,4.8,1e-5\n");
  EXPECT_NE(open_error().find("line 2: gyro_rate 'nan' is not a number"), std::string::npos);
}

TEST_F(Datasets, ScanListWithImuReadings) {
  write("a.pcd", io::encode_binary_pcd(kPoints));
  write("b.pcd", io::encode_binary_pcd(kPoints));
  write("scans.csv",
        "file,stamp,up_x,up_y,up_z,up_sigma,gyro_rate,gyro_seconds,gyro_sigma\n"
        "a.pcd,0,0,0,2,0.01,-5e-5,4.8,7.8e-5\nb.pcd,1,,,,,,,\n");
  const Dataset dataset = open_dataset(dir_);
  ASSERT_TRUE(dataset.scans[0].gravity.has_value());
  EXPECT_EQ(dataset.scans[0].gravity->up_in_base, Eigen::Vector3d::UnitZ()) << "made a unit vector";
  EXPECT_EQ(dataset.scans[0].gravity->sigma, 0.01);
  ASSERT_TRUE(dataset.scans[0].standing_gyro.has_value());
  EXPECT_EQ(dataset.scans[0].standing_gyro->rate, -5e-5);
  EXPECT_EQ(dataset.scans[0].standing_gyro->seconds, 4.8);
  EXPECT_EQ(dataset.scans[0].standing_gyro->sigma, 7.8e-5);
  EXPECT_FALSE(dataset.scans[1].gravity.has_value()) << "empty fields: no reading";
  EXPECT_FALSE(dataset.scans[1].standing_gyro.has_value()) << "empty fields: no stand";
}

TEST_F(Datasets, ADirectoryWithoutADatasetIsAClearError) {
  write("notes.txt", "nothing to replay\n");
  EXPECT_NE(open_error().find("no dataset Strata can replay"), std::string::npos);
  EXPECT_THROW((void)open_dataset(dir_ / "missing"), DatasetError);
}

}  // namespace
}  // namespace strata::replay

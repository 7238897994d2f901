#include "drivers/lidar/velodyne_calibration.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "drivers/lidar/lidar_config_error.hpp"
#include "tests/unit/drivers/lidar/lidar_test_data.hpp"

namespace strata::lidar {
namespace {

constexpr double kDegree = M_PI / 180.0;

std::string error_of(const std::string& yaml) {
  try {
    (void)parse_velodyne_calibration(yaml, "test.yaml");
  } catch (const LidarConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(VelodyneCalibration, ReadsTheStandardFilesAndTheyMatchTheNominalAngles) {
  const std::filesystem::path dir = test::lidar_data_dir();
  STRATA_SKIP_WITHOUT(dir / "32db.yaml");
  const VelodyneCalibration hdl = read_velodyne_calibration(dir / "32db.yaml");
  const VelodyneCalibration vlp = read_velodyne_calibration(dir / "VLP16db.yaml");
  ASSERT_EQ(hdl.lasers.size(), 32u);
  ASSERT_EQ(vlp.lasers.size(), 16u);
  EXPECT_DOUBLE_EQ(hdl.distance_resolution, 0.002);
  EXPECT_NEAR(hdl.lasers[0].vert_correction, -30.67 * kDegree, 1e-4);
  EXPECT_NEAR(hdl.lasers[1].vert_correction, -9.33 * kDegree, 1e-4);
  EXPECT_NEAR(vlp.lasers[1].vert_correction, 1.0 * kDegree, 1e-4);
  const VelodyneCalibration nominal_hdl = nominal_hdl32e_calibration();
  const VelodyneCalibration nominal_vlp = nominal_vlp16_calibration();
  for (std::size_t i = 0; i < 32; ++i) {
    EXPECT_EQ(hdl.lasers[i].laser_id, static_cast<int>(i));
    EXPECT_NEAR(hdl.lasers[i].vert_correction, nominal_hdl.lasers[i].vert_correction, 0.01 * kDegree) << i;
  }
  for (std::size_t i = 0; i < 16; ++i)
    EXPECT_NEAR(vlp.lasers[i].vert_correction, nominal_vlp.lasers[i].vert_correction, 0.01 * kDegree) << i;
}

TEST(VelodyneCalibration, OrdersLasersByIdAndReadsCorrections) {
  const VelodyneCalibration calibration = parse_velodyne_calibration(R"(
lasers:
- {laser_id: 1, vert_correction: 0.1, rot_correction: 0.02, dist_correction: 0.05, vert_offset_correction: 0.01}
- {laser_id: 0, vert_correction: -0.1, horiz_offset_correction: 0.03}
num_lasers: 2
distance_resolution: 0.004
)",
                                                                     "inline");
  ASSERT_EQ(calibration.lasers.size(), 2u);
  EXPECT_DOUBLE_EQ(calibration.lasers[0].vert_correction, -0.1);
  EXPECT_DOUBLE_EQ(calibration.lasers[0].horiz_offset_correction, 0.03);
  EXPECT_DOUBLE_EQ(calibration.lasers[1].rot_correction, 0.02);
  EXPECT_DOUBLE_EQ(calibration.lasers[1].dist_correction, 0.05);
  EXPECT_DOUBLE_EQ(calibration.lasers[1].vert_offset_correction, 0.01);
  EXPECT_DOUBLE_EQ(calibration.distance_resolution, 0.004);
}

TEST(VelodyneCalibration, BadFilesGiveAClearError) {
  EXPECT_NE(error_of("lasers: [ {laser_id: 0, vert_correction: 0.1"), "");  // YAML syntax
  EXPECT_NE(error_of("lasers: [ {laser_id: 0, vert_correction: 0.1").find("not valid YAML"),
            std::string::npos);
  EXPECT_NE(error_of("foo: 1").find("no 'lasers' list"), std::string::npos);
  EXPECT_NE(error_of("lasers: []").find("no 'lasers' list"), std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0}]").find("has no vert_correction"), std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: abc}]").find("vert_correction is not a number"),
            std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: 0}, {laser_id: 0, vert_correction: 0}]")
                .find("appears twice"),
            std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 5, vert_correction: 0}]").find("not in 0..0"), std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: 15.0}]").find("radians"), std::string::npos);
  // Finite but absurd corrections made the decoder's points infinite (found by the fuzz target).
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: 0, dist_correction: 1e300}]")
                .find("dist_correction beyond +-10 m"),
            std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: 0, horiz_offset_correction: -26}]")
                .find("horiz_offset_correction beyond"),
            std::string::npos);
  EXPECT_NE(
      error_of("lasers: [{laser_id: 0, vert_correction: 0, rot_correction: 1e300}]").find("rot_correction"),
      std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: 0}]\nnum_lasers: 32").find("num_lasers is 32"),
            std::string::npos);
  // yaml-cpp refuses more than 2,000 levels (its DeepRecursion) before its recursive parser runs out of
  // stack.
  EXPECT_NE(error_of("lasers: " + std::string(100000, '[')).find("not valid YAML"), std::string::npos);
  EXPECT_NE(error_of("lasers: [{laser_id: 0, vert_correction: 0}]\ndistance_resolution: -1")
                .find("distance_resolution"),
            std::string::npos);
  try {
    (void)read_velodyne_calibration("/nonexistent/db.yaml");
    FAIL();
  } catch (const LidarConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/db.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace strata::lidar

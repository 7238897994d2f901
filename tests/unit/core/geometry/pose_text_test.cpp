#include "core/geometry/pose_text.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <string>

namespace strata {
namespace {

TEST(PoseText, MetresAndDegreesWithCommas) {
  const Pose3 full = parse_pose_text("1.5, -2,0.25,0,-90,180");
  EXPECT_EQ(full.position, Eigen::Vector3d(1.5, -2, 0.25));
  EXPECT_DOUBLE_EQ(full.roll, 0.0);
  EXPECT_DOUBLE_EQ(full.pitch, -std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(full.yaw, std::numbers::pi);
  const Pose3 position_only = parse_pose_text("0,0,1.2");
  EXPECT_EQ(position_only.position, Eigen::Vector3d(0, 0, 1.2));
  EXPECT_DOUBLE_EQ(position_only.yaw, 0.0);
}

TEST(PoseText, SaysWhatIsWrong) {
  for (const std::string bad : {"", "1,2", "1,2,3,4", "1,2,3,4,5,6,7", "1,x,3", "1,2,3m", "1,nan,3",
                                "1,inf,3", "1 2 3 4 5 6", "1,,3"}) {
    EXPECT_THROW((void)parse_pose_text(bad), std::invalid_argument) << bad;
  }
  try {
    (void)parse_pose_text("1,2");
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("x,y,z or x,y,z,roll,pitch,yaw"), std::string::npos);
  }
}

TEST(PoseText, APointIsThreeNumbersInMetres) {
  EXPECT_TRUE(parse_point_text("1.5,-2, 0.25").isApprox(Eigen::Vector3d(1.5, -2.0, 0.25)));
  for (const std::string bad : {"1,2", "1,2,3,0,0,0", "1,nan,3", "1 2 3"})
    EXPECT_THROW((void)parse_point_text(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace strata

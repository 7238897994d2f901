#include "drivers/sim/imu.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace strata::sim {
namespace {

TEST(SimulatedImu, WithoutNoiseItMeasuresTheTruth) {
  SimulatedImu imu({.gyro_bias_stddev = 0.0,
                    .gyro_noise_density = 0.0,
                    .tilt_bias_stddev = 0.0,
                    .tilt_noise_standing = 0.0,
                    .tilt_noise_moving = 0.0},
                   1);
  EXPECT_DOUBLE_EQ(imu.measure_turn(0.25, 0.02), 0.25);
  const Pose3 truth{{1.0, 2.0, 3.0}, 0.1, -0.2, 1.0};
  const GravityReading reading = imu.measure_gravity(truth, true);
  const Eigen::Vector3d up_in_map = truth.to_isometry().linear() * reading.up_in_base;
  EXPECT_NEAR((up_in_map - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
}

TEST(SimulatedImu, TheGyroDriftsFarLessThanItTurns) {
  // Ten minutes standing still, 50 Hz: a consumer gyro's bias and noise add up to a fraction of a degree.
  SimulatedImu imu({}, 7);
  double heading = 0.0;
  for (int i = 0; i < 30000; ++i)
    heading += imu.measure_turn(0.0, 0.02);
  EXPECT_GT(std::abs(heading), 0.0);
  EXPECT_LT(std::abs(heading), 0.15);
}

TEST(SimulatedImu, StandingItsGyroReadsItsBiasAndLeavesTheTurnsAsTheyWere) {
  SimulatedImu standing({.gyro_bias_stddev = 1e-4}, 9);
  SimulatedImu driving({.gyro_bias_stddev = 1e-4}, 9);
  ASSERT_GT(std::abs(standing.gyro_bias()), 2e-5) << "seed 9 draws a bias to find";
  double turned = 0.0;
  constexpr double kSeconds = 1000.0;
  for (int i = 0; i < 50000; ++i)
    turned += standing.measure_standing_turn(kSeconds / 50000);
  // The mean rate is the bias, but for the noise over 1000 s: 1.7e-4 / sqrt(1000) rad/s.
  EXPECT_NEAR(turned / kSeconds, standing.gyro_bias(), 3.0 * 1.7e-4 / std::sqrt(kSeconds));
  EXPECT_EQ(standing.measure_turn(0.1, 0.02), driving.measure_turn(0.1, 0.02))
      << "a sequence of its own: the odometry's turns are the same read or not";
}

TEST(SimulatedImu, GravityIsReadWithinItsStatedSigma) {
  SimulatedImu imu({}, 3);
  const Pose3 truth{{0.0, 0.0, 0.0}, 0.2, 0.1, -2.0};
  for (bool standing : {true, false}) {
    const GravityReading reading = imu.measure_gravity(truth, standing);
    const Eigen::Vector3d up_in_map = truth.to_isometry().linear() * reading.up_in_base;
    const double error = std::acos(std::clamp(up_in_map.z(), -1.0, 1.0));
    EXPECT_NEAR(reading.up_in_base.norm(), 1.0, 1e-12);
    EXPECT_LT(error, 5.0 * reading.sigma) << (standing ? "standing" : "moving");
  }
  EXPECT_LT(imu.measure_gravity(truth, true).sigma, imu.measure_gravity(truth, false).sigma)
      << "an accelerometer on a driving base feels its accelerations too";
}

TEST(SimulatedImu, SameSeedSameReadings) {
  SimulatedImu a({}, 11);
  SimulatedImu b({}, 11);
  EXPECT_EQ(a.measure_turn(0.1, 0.02), b.measure_turn(0.1, 0.02));
  const Pose3 truth{{0.0, 0.0, 0.0}, 0.05, 0.0, 0.0};
  EXPECT_EQ(a.measure_gravity(truth, true).up_in_base, b.measure_gravity(truth, true).up_in_base);
}

}  // namespace
}  // namespace strata::sim

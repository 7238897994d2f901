#include "core/localization/heading_drift.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace strata {
namespace {

/// Keyframes every 5 s of motion for `seconds`: the odometry's heading drifts `bias` rad/s off the truth
/// (a turning path), the graph's estimate is on the truth but for `noise` radians.
std::vector<HeadingSample> drifting_run(double seconds, double bias, double noise, double start = 0.3) {
  std::mt19937 rng(7);
  std::normal_distribution<double> error(0.0, noise);
  std::vector<HeadingSample> samples;
  for (double t = 0.0; t <= seconds; t += 5.0) {
    const double truth = start + 0.02 * t;  // turning: about a turn every five minutes
    samples.push_back({.seconds = t,
                       .odometry_heading = truth + bias * t,
                       .estimated_heading = std::remainder(truth + error(rng), 2.0 * std::numbers::pi)});
  }
  return samples;
}

TEST(HeadingDrift, IsTheSlopeOfTheEstimatesHeadingAgainstTheOdometrys) {
  // A consumer gyro's 12 degrees an hour; the graph's headings a quarter of a degree off each.
  const std::vector<HeadingSample> samples = drifting_run(800.0, -6e-5, 0.004);
  const std::optional<double> drift = fit_heading_drift(samples);
  ASSERT_TRUE(drift.has_value());
  EXPECT_NEAR(*drift, 6e-5, 0.5e-5) << "radians to add per second: the bias taken out";
  // Through the heading's wrap at half a turn (the samples go round several times) and from either side.
  const std::optional<double> around = fit_heading_drift(drifting_run(800.0, 6e-5, 0.0, 3.1));
  ASSERT_TRUE(around.has_value());
  EXPECT_NEAR(*around, -6e-5, 1e-9);
}

TEST(HeadingDrift, FitsTheLastWindowOfMotionOnly) {
  // The bias changed (the gyro warmed up): the fit follows the last window, not the whole run.
  std::vector<HeadingSample> samples = drifting_run(1200.0, 2e-4, 0.0);
  for (HeadingSample& sample : samples)
    if (sample.seconds > 600.0)
      sample.odometry_heading += -3e-4 * (sample.seconds - 600.0);  // 2e-4 -> -1e-4 from 600 s on
  const std::optional<double> drift = fit_heading_drift(samples, {.window = 500.0, .min_window = 300.0});
  ASSERT_TRUE(drift.has_value());
  EXPECT_NEAR(*drift, 1e-4, 1e-9);
}

TEST(HeadingDrift, FitsNothingOverTooLittleMotionOrToAnImplausibleSlope) {
  EXPECT_FALSE(fit_heading_drift(drifting_run(200.0, 6e-5, 0.0), {.min_window = 300.0}).has_value())
      << "200 s: too short to tell a drift from the estimate's errors";
  EXPECT_FALSE(fit_heading_drift(drifting_run(800.0, 6e-3, 0.0)).has_value())
      << "a degree every 3 s is no odometry's drift (a map turning under the robot)";
  EXPECT_FALSE(fit_heading_drift(drifting_run(800.0, 6e-5, 0.0), {.enabled = false}).has_value());
  EXPECT_FALSE(fit_heading_drift({}).has_value());
}

/// Stands of `seconds` each whose gyro reads `bias` rad/s, with a consumer gyro's noise (1.7e-4 rad/sqrt(s)).
std::vector<StandingGyro> stands(int count, double bias, double seconds = 4.8, unsigned seed = 3) {
  constexpr double kDensity = 1.7e-4;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kDensity / std::sqrt(seconds));
  std::vector<StandingGyro> out;
  for (int i = 0; i < count; ++i)
    out.push_back({.rate = bias + noise(rng), .seconds = seconds, .sigma = kDensity / std::sqrt(seconds)});
  return out;
}

TEST(StandingGyroDrift, IsTheBiasTheGyroReadsStandingOnceItIsSure) {
  StandingGyroDrift drift;  // sure to 1.5e-5 rad/s: some 27 stands of 4.8 s
  const std::vector<StandingGyro> readings = stands(100, 6e-5);
  for (std::size_t i = 0; i < 20; ++i)
    drift.add(readings[i]);
  EXPECT_FALSE(drift.drift().has_value()) << "20 stands tell the bias to 1.7e-5 rad/s, not yet sure";
  for (std::size_t i = 20; i < readings.size(); ++i)
    drift.add(readings[i]);
  ASSERT_TRUE(drift.drift().has_value());
  EXPECT_NEAR(drift.sigma(), 1.7e-4 / std::sqrt(480.0), 1e-9);
  EXPECT_NEAR(*drift.drift(), -6e-5, 3.0 * drift.sigma()) << "radians to add per second: the bias taken out";
  // A long stand counts for more than a short one: weighed by their sigmas.
  StandingGyroDrift weighed({.standing_max_sigma = 1.0});
  weighed.add({.rate = 1e-4, .seconds = 1.0, .sigma = 2e-4});
  weighed.add({.rate = 4e-4, .seconds = 16.0, .sigma = 5e-5});
  ASSERT_TRUE(weighed.drift().has_value());
  EXPECT_NEAR(*weighed.drift(), -(1e-4 * 1.0 + 4e-4 * 16.0) / 17.0, 1e-12);
}

TEST(StandingGyroDrift, FollowsTheLastWindowOfStandingAndTakesNoBadReading) {
  // The bias changed (the gyro warmed up): the last hour of standing tells it, not the first.
  StandingGyroDrift drift;
  for (const StandingGyro& stand : stands(800, 6e-5))
    drift.add(stand);
  for (const StandingGyro& stand : stands(800, -2e-5, 4.8, 4))
    drift.add(stand);
  ASSERT_TRUE(drift.drift().has_value());
  EXPECT_NEAR(*drift.drift(), 2e-5, 3.0 * drift.sigma());
  // Not finite, no time, no sigma: nothing changes.
  const double before = *drift.drift();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  drift.add({.rate = nan, .seconds = 4.8, .sigma = 1e-5});
  drift.add({.rate = 1.0, .seconds = 0.0, .sigma = 1e-5});
  drift.add({.rate = 1.0, .seconds = 4.8, .sigma = 0.0});
  drift.add({.rate = 1.0, .seconds = std::numeric_limits<double>::infinity(), .sigma = 1e-5});
  EXPECT_EQ(*drift.drift(), before);
  EXPECT_FALSE(StandingGyroDrift({.enabled = false}).drift().has_value());
  EXPECT_FALSE(StandingGyroDrift().drift().has_value()) << "no stand yet";
}

}  // namespace
}  // namespace strata

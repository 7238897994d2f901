#include "core/localization/heading_drift.hpp"

#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace strata

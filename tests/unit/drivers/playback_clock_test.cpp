#include "drivers/playback_clock.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace strata {
namespace {

TEST(PlaybackClock, AsFastAsPossibleNeverWaitsForTimeButForThePipeline) {
  PlaybackClock clock({.time_scale = 1e-9, .as_fast_as_possible = true});  // the scale is not used
  EXPECT_EQ(clock.description(), "as fast as possible");
  int asked = 0;
  const RobotDriver::PipelineIdle idle = [&] { return ++asked < 3; };  // the pipeline stops on the third
  for (double stamp : {0.0, 3600.0, 7200.0})
    EXPECT_TRUE(clock.wait_until_due(stamp)) << "an hour of recorded time takes none";
  EXPECT_TRUE(clock.wait_for_pipeline(idle));
  EXPECT_TRUE(clock.wait_for_pipeline(idle));
  EXPECT_FALSE(clock.wait_for_pipeline(idle));
  EXPECT_EQ(asked, 3);
  EXPECT_TRUE(clock.wait_for_pipeline({})) << "no pipeline to wait for";
}

TEST(PlaybackClock, ByTheRecordedClockThePipelineIsNotAskedAndStopEndsAWait) {
  PlaybackClock clock({.time_scale = 2.0});
  EXPECT_EQ(clock.description(), "time scale 2");
  EXPECT_TRUE(clock.wait_until_due(100.0)) << "the first stamp is due at once";
  EXPECT_TRUE(clock.wait_for_pipeline([] {
    ADD_FAILURE() << "a paced playback does not wait for the pipeline";
    return true;
  }));
  // A stamp a year later: only stop() can end this wait.
  std::thread stopper([&] { clock.stop(); });
  EXPECT_FALSE(clock.wait_until_due(100.0 + 365 * 86400.0));
  stopper.join();
  EXPECT_TRUE(clock.stopped());
  EXPECT_FALSE(clock.wait_until_due(100.0)) << "stopped for good";
  EXPECT_FALSE(clock.wait_for_pipeline({}));
}

TEST(PlaybackClock, ATimeScaleThatIsNotPositiveIsRefused) {
  for (double scale : {0.0, -1.0, std::nan("")})
    EXPECT_THROW(PlaybackClock({.time_scale = scale}), std::invalid_argument) << scale;
  EXPECT_EQ(PlaybackClock({.time_scale = 0.25}).description(), "time scale 0.25");
}

}  // namespace
}  // namespace strata

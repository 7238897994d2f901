#include "server/state/sensor_watch.hpp"

#include <gtest/gtest.h>

namespace strata {
namespace {

using namespace std::chrono_literals;
using Time = SensorWatch::Clock::time_point;

constexpr Time kStart{100s};

TEST(SensorWatch, OkWhileScansComeAsDue) {
  SensorWatch watch(2.0);
  EXPECT_FALSE(watch.status(kStart).seconds_since_last_scan.has_value());
  watch.sample(true, kStart);
  for (int i = 1; i <= 10; ++i) {
    watch.sample(true, kStart + i * 1s);
    watch.scan(kStart + i * 1s);
  }
  const SensorStatus status = watch.status(kStart + 10s + 500ms);
  EXPECT_FALSE(status.stalled);
  EXPECT_EQ(status.scans, 10U);
  EXPECT_DOUBLE_EQ(*status.seconds_since_last_scan, 0.5);
  EXPECT_DOUBLE_EQ(status.overdue, 0.5);
  EXPECT_DOUBLE_EQ(status.timeout, 2.0);
}

TEST(SensorWatch, StallsWhenADueScanIsLateAndRecoversWithTheNextScan) {
  SensorWatch watch(2.0);
  watch.sample(true, kStart);
  watch.scan(kStart);
  for (int i = 1; i <= 30; ++i)
    watch.sample(true, kStart + i * 100ms);
  EXPECT_TRUE(watch.status(kStart + 3s).stalled);
  EXPECT_DOUBLE_EQ(watch.status(kStart + 3s).overdue, 3.0);
  watch.scan(kStart + 3s);
  EXPECT_FALSE(watch.status(kStart + 3s).stalled);
  EXPECT_EQ(watch.status(kStart + 3s).scans, 2U);
}

TEST(SensorWatch, ADriverThatFallsSilentWhileAScanIsDueStallsToo) {
  SensorWatch watch(2.0);
  watch.sample(true, kStart);
  watch.scan(kStart);
  // No sample, no scan: the last sample said a scan was due.
  EXPECT_FALSE(watch.status(kStart + 1s).stalled);
  EXPECT_TRUE(watch.status(kStart + 5s).stalled);
}

// The stop-and-go scanner owes a scan only while it scans: standing or driving between scans for a long
// time is not a stalled sensor, and only the time spent scanning counts.
TEST(SensorWatch, OnlyTheStretchesWhenAScanIsDueCount) {
  SensorWatch watch(2.0);
  watch.sample(false, kStart);
  watch.sample(false, kStart + 60s);  // a minute of driving
  EXPECT_FALSE(watch.status(kStart + 60s).stalled);
  EXPECT_FALSE(watch.status(kStart + 120s).stalled);  // and standing still, no samples needed
  watch.sample(true, kStart + 120s);                  // starts a scan
  watch.sample(false, kStart + 121s);                 // the scan was lost; drives on
  watch.sample(true, kStart + 200s);                  // tries again
  EXPECT_DOUBLE_EQ(watch.status(kStart + 200s).overdue, 1.0);
  EXPECT_FALSE(watch.status(kStart + 200s).stalled);
  EXPECT_TRUE(watch.status(kStart + 201s + 500ms).stalled);  // 1 s + 1.5 s of scanning without a scan
}

TEST(SensorWatch, AFinishedReplayOwesNothing) {
  SensorWatch watch(2.0);
  watch.sample(true, kStart);
  watch.scan(kStart);
  watch.finished();
  watch.sample(true, kStart + 10s);
  EXPECT_FALSE(watch.status(kStart + 60s).stalled);
  EXPECT_DOUBLE_EQ(*watch.status(kStart + 60s).seconds_since_last_scan, 60.0);
}

}  // namespace
}  // namespace strata

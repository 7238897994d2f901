// A place a search found is the robot's only once the scans after it match there.
#include "core/localization/relocalization_tracker.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace strata {
namespace {

std::shared_ptr<const LocalizationMap> floor_map() {
  auto map = std::make_shared<LocalizationMap>();
  for (float x = -2.0F; x <= 2.0F; x += 0.2F)
    for (float y = -2.0F; y <= 2.0F; y += 0.2F)
      map->points.emplace_back(x, y, 0.0F);
  map->keyframe_poses = {Eigen::Isometry3d::Identity()};
  return map;
}

LocalizationUpdate registered(Correction correction) {
  LocalizationUpdate update;
  update.correction = correction;
  update.registration = RegistrationResult{};
  update.registration->assessment.message = "12.0 m from the guess";
  return update;
}

TEST(RelocalizationTracker, APlaceIsConfirmedWhenTheNextScansMatchThere) {
  RelocalizationTracker tracker(floor_map());
  EXPECT_EQ(tracker.check_placement(registered(Correction::kFull), 1.0), PlacementCheck::kNone);
  tracker.placed(10.0);
  EXPECT_EQ(tracker.check_placement(registered(Correction::kFull), 10.0), PlacementCheck::kPending)
      << "the scan it was found with agrees with itself";
  EXPECT_EQ(tracker.check_placement(registered(Correction::kPartial), 12.0), PlacementCheck::kPending);
  EXPECT_EQ(tracker.check_placement(registered(Correction::kNone), 14.0), PlacementCheck::kPending)
      << "one refused scan happens on any run";
  EXPECT_EQ(tracker.check_placement(registered(Correction::kFull), 16.0), PlacementCheck::kConfirmed);
  EXPECT_EQ(tracker.check_placement(registered(Correction::kNone), 18.0), PlacementCheck::kNone);
  const std::vector<RelocalizationReport> reports = tracker.take_reports();
  ASSERT_EQ(reports.size(), 1U);
  EXPECT_TRUE(reports[0].found);
  EXPECT_EQ(reports[0].search, RelocalizationReport::Search::kCheck);
  EXPECT_EQ(reports[0].message, "the place found at t=10.0 is confirmed: the next 2 scans matched there");
}

TEST(RelocalizationTracker, APlaceWhoseNextScansAreRefusedWasWrong) {
  RelocalizationTracker tracker(floor_map());
  tracker.placed(10.0);
  EXPECT_EQ(tracker.check_placement(registered(Correction::kNone), 12.0), PlacementCheck::kPending);
  EXPECT_EQ(tracker.check_placement(registered(Correction::kNone), 14.0), PlacementCheck::kContradicted);
  const std::vector<RelocalizationReport> reports = tracker.take_reports();
  ASSERT_EQ(reports.size(), 1U);
  EXPECT_FALSE(reports[0].found);
  EXPECT_EQ(reports[0].message,
            "the place found at t=10.0 was wrong: 2 of the next scans were refused there (12.0 m from the "
            "guess)");
}

}  // namespace
}  // namespace strata

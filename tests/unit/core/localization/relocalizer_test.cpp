#include "core/localization/relocalizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/pipeline/scan_preprocessing.hpp"
#include "tests/support/sim_saved_map.hpp"

namespace strata {
namespace {

struct Seen {
  PointCloud points;
  Eigen::Isometry3d truth;
};

/// Scans of another run (seed 2) through the same yard, at their true poses.
std::vector<Seen> second_run(const std::shared_ptr<const sim::World>& world, std::size_t count) {
  std::vector<Seen> seen;
  sim::Simulator run(world, {.seed = 2});
  while (seen.size() < count) {
    run.step(0.01);
    for (const ScanEvent& scan : run.take_scans())
      seen.push_back({pipeline::points_in_base(scan), scan.truth->to_isometry()});
  }
  return seen;
}

double heading_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::abs(std::remainder(heading_of(a) - heading_of(b), 2.0 * std::numbers::pi));
}

// A hint 1.4 m and 25 degrees off finds the robot to centimetres, on the ground and up on the platform;
// without a hint every place the map's robot drove is tried; a scan of somewhere else is not placed.
TEST(Relocalizer, FindsTheRobotFromAHintAndWithoutOne) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  Relocalizer relocalizer(std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 14)));
  const std::vector<Seen> seen = second_run(world, 12);
  for (const std::size_t i : {2U, 3U, 7U, 11U}) {
    const Eigen::Isometry3d& truth = seen[i].truth;
    const RelocalizationResult hinted =
        relocalizer.around(seen[i].points, truth.translation().x() + 1.0, truth.translation().y() - 1.0,
                           heading_of(truth) + 0.44);
    ASSERT_TRUE(hinted.found) << "scan " << i << ": " << hinted.message;
    EXPECT_LT((hinted.pose.translation() - truth.translation()).norm(), 0.1) << "scan " << i;
    EXPECT_LT(heading_error(hinted.pose, truth), 1.0 * std::numbers::pi / 180.0) << "scan " << i;

    // Told apart by the walls and the platform, not the ground: found, and in the right place (the ground
    // alone fitted the yard's mirror image 14 m away as well).
    const RelocalizationResult anywhere = relocalizer.anywhere(seen[i].points);
    EXPECT_GT(anywhere.candidates, 100U);
    ASSERT_TRUE(anywhere.found) << "scan " << i << ": " << anywhere.message;
    EXPECT_LT((anywhere.pose.translation() - truth.translation()).norm(), 0.2) << "scan " << i;
  }
  // The same scan with nothing above the ground: too many places have ground like it to search them all,
  // but near a hint its shape is searched.
  PointCloud ground;
  for (const Eigen::Vector3d& p : seen[3].points)
    if (p.z() < 0.2)
      ground.push_back(p);
  const RelocalizationResult bare = relocalizer.anywhere(ground);
  EXPECT_FALSE(bare.found);
  EXPECT_NE(bare.message.find("nothing but ground"), std::string::npos) << bare.message;
  const RelocalizationResult near =
      relocalizer.around(ground, seen[3].truth.translation().x() + 0.3, seen[3].truth.translation().y(),
                         heading_of(seen[3].truth));
  EXPECT_EQ(near.message.find("nothing but ground"), std::string::npos) << near.message;
  // The corridor world's scan, looked for in the yard.
  auto corridor = std::make_shared<const sim::World>(sim::builtin_world("campus"));
  const std::vector<Seen> elsewhere = second_run(corridor, 1);
  const RelocalizationResult lost = relocalizer.anywhere(elsewhere[0].points);
  EXPECT_FALSE(lost.found) << lost.message;
  EXPECT_FALSE(lost.message.empty());
}

// A scan taken on a ramp (5.7 degrees) is found from a hint: the candidates stand on the ground the map's
// keyframes stood on. Level candidates put the scan's far points a metre off the ramp, and no candidate
// was refined into the right place (the campus's bridge ramp: none of its samples found). Without a hint
// the yard's two ramps, mirror images, may fit as well: then refused, never the wrong one.
TEST(Relocalizer, FindsTheRobotOnARamp) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  Relocalizer relocalizer(std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 14)));
  const std::vector<Seen> seen = second_run(world, 30);
  std::size_t on_ramps = 0;
  for (const Seen& s : seen) {
    const double tilt = std::acos(std::clamp(s.truth.linear()(2, 2), -1.0, 1.0));
    if (tilt < 4.0 * std::numbers::pi / 180.0)
      continue;
    ++on_ramps;
    const Eigen::Isometry3d& truth = s.truth;
    const RelocalizationResult hinted = relocalizer.around(
        s.points, truth.translation().x() - 0.8, truth.translation().y() + 0.6, heading_of(truth) - 0.3);
    ASSERT_TRUE(hinted.found) << hinted.message;
    EXPECT_LT((hinted.pose.translation() - truth.translation()).norm(), 0.1);
    EXPECT_LT(heading_error(hinted.pose, truth), 1.0 * std::numbers::pi / 180.0);
    const RelocalizationResult anywhere = relocalizer.anywhere(s.points);
    if (anywhere.found)
      EXPECT_LT((anywhere.pose.translation() - truth.translation()).norm(), 0.1) << anywhere.message;
    else
      EXPECT_NE(anywhere.message.find("two places fit as well"), std::string::npos) << anywhere.message;
  }
  EXPECT_GT(on_ramps, 0U) << "the run's first scans include one on a ramp";
}

// A place is judged by the walls and objects the map has there, and those must fit closely. A map that
// never saw part of what the scan sees still places it, and so does a map of one sparse scan; a scan
// whose every seventh wall point lies 0.3 m off the map's walls (the way a place 0.4 m along a path
// fitted: 89 % of them within 10 cm) does not.
TEST(Relocalizer, JudgesAPlaceByTheWallsTheMapHasThereAndNeedsThemClose) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  const LocalizationMap full = test::saved_map_of_run(world, 14);
  const std::vector<Seen> seen = second_run(world, 4);
  const Eigen::Isometry3d& truth = seen[3].truth;

  // The map without what lies beyond 4 m to one side of the robot.
  LocalizationMap partial = full;
  std::erase_if(partial.points,
                [&](const Eigen::Vector3f& p) { return (truth.inverse() * p.cast<double>()).y() > 4.0; });
  ASSERT_LT(partial.points.size(), full.points.size());
  Relocalizer on_partial(std::make_shared<const LocalizationMap>(partial));
  const RelocalizationResult found = on_partial.around(
      seen[3].points, truth.translation().x() + 0.5, truth.translation().y() - 0.5, heading_of(truth) + 0.2);
  ASSERT_TRUE(found.found) << found.message;
  EXPECT_LT((found.pose.translation() - truth.translation()).norm(), 0.1);
  EXPECT_LT(found.structure_share, 0.9) << "the scan sees walls the partial map lacks";
  EXPECT_GE(found.covered_structure_share, 0.9);

  // Every seventh point above the ground moved 0.3 m away from the scanner.
  PointCloud loose = seen[3].points;
  std::size_t structure = 0;
  for (Eigen::Vector3d& p : loose)
    if (p.z() > 0.3 && structure++ % 7 == 0)
      p += 0.3 * Eigen::Vector3d(p.x(), p.y(), 0.0).normalized();
  Relocalizer on_full(std::make_shared<const LocalizationMap>(full));
  const RelocalizationResult refused = on_full.around(loose, truth.translation().x() + 0.5,
                                                      truth.translation().y() - 0.5, heading_of(truth) + 0.2);
  EXPECT_FALSE(refused.found) << refused.message;
  EXPECT_NE(refused.message.find("fits closely"), std::string::npos) << refused.message;
  const RelocalizationResult intact = on_full.around(seen[3].points, truth.translation().x() + 0.5,
                                                     truth.translation().y() - 0.5, heading_of(truth) + 0.2);
  EXPECT_TRUE(intact.found) << intact.message;

  // A map of the first scan alone, its far walls' points 0.2 m apart: the next scan's walls lie on its
  // surfaces, if not within 10 cm of its points (81 % of them are).
  const auto one_scan = std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 1));
  const Eigen::Isometry3d& next = seen[1].truth;
  const RelocalizationResult on_surfaces = Relocalizer(one_scan).around(
      seen[1].points, next.translation().x() + 0.5, next.translation().y(), heading_of(next) + 0.2);
  ASSERT_TRUE(on_surfaces.found) << on_surfaces.message;
  EXPECT_LT((on_surfaces.pose.translation() - next.translation()).norm(), 0.1);
  const RelocalizationResult on_points = Relocalizer(one_scan, {.surface_reach = 0.0})
                                             .around(seen[1].points, next.translation().x() + 0.5,
                                                     next.translation().y(), heading_of(next) + 0.2);
  EXPECT_FALSE(on_points.found) << on_points.message;
}

// Places a scan fitted as well, followed into the next scan (moved as the robot moved): the place that
// scan fits is kept, the other dropped, and taken once a scan's fit leaves it where it was; with no place
// there is nothing to take.
TEST(Relocalizer, FollowingPlacesKeepsTheOneTheNextScanFits) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  Relocalizer relocalizer(std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 14)));
  const std::vector<Seen> seen = second_run(world, 8);
  const Eigen::Isometry3d& truth = seen[7].truth;
  Eigen::Isometry3d near = truth;
  near.translation() += Eigen::Vector3d(0.15, -0.1, 0.0);
  Eigen::Isometry3d elsewhere = truth;
  elsewhere.translation() += Eigen::Vector3d(3.0, 2.0, 0.0);
  // The scan moves the near place 0.18 m onto the truth: not taken yet, followed on from there.
  const RelocalizationResult moved = relocalizer.follow(seen[7].points, {elsewhere, near});
  ASSERT_FALSE(moved.found) << moved.message;
  EXPECT_NE(moved.message.find("moved"), std::string::npos) << moved.message;
  ASSERT_EQ(moved.places.size(), 1U) << moved.message;
  EXPECT_LT((moved.places.front().translation() - truth.translation()).norm(), 0.1);
  // The next scan (here the same, the robot standing) leaves it there: taken.
  const RelocalizationResult followed = relocalizer.follow(seen[7].points, moved.places);
  ASSERT_TRUE(followed.found) << followed.message;
  EXPECT_LT((followed.pose.translation() - truth.translation()).norm(), 0.1);
  EXPECT_TRUE(followed.places.empty());
  EXPECT_GT(followed.candidates, 1U);  // the place, and a search around it

  const RelocalizationResult none = relocalizer.follow(seen[7].points, {});
  EXPECT_FALSE(none.found);
  EXPECT_FALSE(none.message.empty());

  // The same scan's ground alone decides nothing, not even with one place to follow: flat ground fits
  // wherever the places stand. The places go on to the next scan.
  PointCloud ground;
  for (const Eigen::Vector3d& p : seen[7].points)
    if (p.z() < 0.2)
      ground.push_back(p);
  for (const std::vector<Eigen::Isometry3d>& places :
       {std::vector<Eigen::Isometry3d>{elsewhere, near}, std::vector<Eigen::Isometry3d>{near}}) {
    const RelocalizationResult bare = relocalizer.follow(ground, places);
    EXPECT_FALSE(bare.found) << bare.message;
    EXPECT_NE(bare.message.find("nothing but ground"), std::string::npos) << bare.message;
    EXPECT_FALSE(bare.places.empty());
    EXPECT_LE(bare.places.size(), places.size());
  }
}

// The places a hallway's scan left can all be metres off; the next scans then fit none of them. The
// robot is then looked for in the whole map with the scan that dropped them.
TEST(Relocalizer, AScanThatFitsNoneOfThePlacesFollowedIsSearchedForInTheWholeMap) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  Relocalizer relocalizer(std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 14)));
  const std::vector<Seen> seen = second_run(world, 8);
  const Eigen::Isometry3d& truth = seen[7].truth;
  std::vector<Eigen::Isometry3d> wrong(2, truth);
  wrong[0] = wrong[0] * Eigen::AngleAxisd(2.5, Eigen::Vector3d::UnitZ());
  wrong[0].translation() += Eigen::Vector3d(8.0, 5.0, 0.0);
  wrong[1] = wrong[1] * Eigen::AngleAxisd(-2.0, Eigen::Vector3d::UnitZ());
  wrong[1].translation() += Eigen::Vector3d(-6.0, 2.0, 0.0);
  const RelocalizationResult followed = relocalizer.follow(seen[7].points, wrong);
  ASSERT_TRUE(followed.found) << followed.message;
  EXPECT_LT((followed.pose.translation() - truth.translation()).norm(), 0.1);
  EXPECT_LT(heading_error(followed.pose, truth), 0.035);
  EXPECT_NE(followed.message.find("whole map"), std::string::npos) << followed.message;
  EXPECT_GT(followed.candidates, wrong.size());
}

// A hint's search that fitted nothing well enough still says where its best candidate was, for the next
// scans to judge; one that found the robot, or registered nothing, leaves nothing to follow.
TEST(Relocalizer, ASearchThatFitsNothingLeavesItsBestPlaceToFollow) {
  auto world = std::make_shared<const sim::World>(sim::builtin_world("yard"));
  Relocalizer relocalizer(std::make_shared<const LocalizationMap>(test::saved_map_of_run(world, 14)));
  const std::vector<Seen> seen = second_run(world, 8);
  const Eigen::Isometry3d& truth = seen[7].truth;
  // The scan with two walls the map does not have (a parked truck, a new fence): the right place fits the
  // rest, but too little of the scan's walls to be taken.
  PointCloud changed = seen[7].points;
  for (double a = -5.0; a <= 5.0; a += 0.05)
    for (double z = 0.4; z <= 2.4; z += 0.05) {
      changed.push_back(Eigen::Vector3d(3.5, a, z));
      changed.push_back(Eigen::Vector3d(a, 3.5, z));
    }
  const RelocalizationResult refused =
      relocalizer.around(changed, truth.translation().x(), truth.translation().y(), heading_of(truth));
  ASSERT_FALSE(refused.found) << refused.message;
  ASSERT_TRUE(refused.refined);
  const std::vector<Eigen::Isometry3d> places = refused.places_to_follow();
  ASSERT_FALSE(places.empty()) << refused.message;
  EXPECT_LT((places.front().translation() - truth.translation()).norm(), 0.2) << refused.message;
  EXPECT_EQ(places.front().matrix(),
            (refused.places.empty() ? refused.pose : refused.places.front()).matrix());

  const RelocalizationResult found =
      relocalizer.around(seen[7].points, truth.translation().x(), truth.translation().y(), heading_of(truth));
  ASSERT_TRUE(found.found) << found.message;
  EXPECT_TRUE(found.places_to_follow().empty());
  EXPECT_TRUE(relocalizer.around({}, 0.0, 0.0, 0.0).places_to_follow().empty());
}

// A place about to be taken is refined again from starts to each side of it. Here a long wall and the
// ground hold a scan anywhere along the wall, and a post tells where: a start 1.75 m along the wall stays
// there (the post's points beyond ICP's reach) and, fitting 86 % of its structure, would be taken. A
// start 0.3 m nearer brings the post in reach, and the robot is found where it is.
TEST(Relocalizer, APlaceAboutToBeTakenIsLookedForInTheBasinsBesideIt) {
  LocalizationMap map;
  const auto add = [&](double x, double y, double z) { map.points.emplace_back(x, y, z); };
  for (double x = -12.0; x <= 12.0; x += 0.1)
    for (double y = -6.0; y <= 6.0; y += 0.1)
      add(x, y, 0.0);  // the ground
  for (double x = -12.0; x <= 12.0; x += 0.1)
    for (double z = 0.1; z <= 2.0; z += 0.1)
      add(x, 3.0, z);  // the wall
  for (double a = -0.3; a <= 0.3 + 1e-9; a += 0.1)
    for (double z = 0.1; z <= 2.0; z += 0.1) {  // the post, 0.6 m square, 2 m ahead-right
      add(2.0 + a, -2.3, z);
      add(2.0 + a, -1.7, z);
      add(1.7, -2.0 + a, z);
      add(2.3, -2.0 + a, z);
    }
  map.keyframe_poses = {Eigen::Isometry3d::Identity()};
  PointCloud scan;  // the robot at the origin, heading along x, sees all within 8 m
  for (const Eigen::Vector3f& p : map.points)
    if (p.head<2>().norm() <= 8.0F)
      scan.push_back(p.cast<double>());
  const auto shared = std::make_shared<const LocalizationMap>(map);
  // One start only (the grid's step longer than the radius): at the hint, 1.75 m along the wall, the
  // place within the radius searched.
  const RelocalizationOptions one_start{
      .hint_radius = 1.8, .hint_yaw = 0.0, .position_step = 2.0, .refined = 1};
  RelocalizationOptions no_basins = one_start;
  no_basins.basin_step = 0.0;
  const RelocalizationResult stayed = Relocalizer(shared, no_basins).around(scan, 1.75, 0.0, 0.0, 0.0);
  ASSERT_TRUE(stayed.found) << stayed.message;
  EXPECT_NEAR(stayed.pose.translation().x(), 1.75, 0.1) << "the post pulled it after all";
  const RelocalizationResult found = Relocalizer(shared, one_start).around(scan, 1.75, 0.0, 0.0, 0.0);
  ASSERT_TRUE(found.found) << found.message;
  EXPECT_LT(found.pose.translation().norm(), 0.05);
  EXPECT_GT(found.structure_share, stayed.structure_share);
}

}  // namespace
}  // namespace strata

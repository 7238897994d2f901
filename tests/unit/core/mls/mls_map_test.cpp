#include "core/mls/mls_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>

#include "core/mls/drivable_map.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata {
namespace {

/// Hand-made scenes are point sets without occlusion, so free-space clearing (which assumes real rays)
/// stays off in them; the dynamic-surface tests build occlusion-consistent scans and turn it on.
MlsConfig static_scene_config(double gap = 1.0) {
  MlsConfig config;
  config.gap = gap;
  config.free_space_ray_stride = 0;
  return config;
}

CellRegion region_of(const MlsMap& map, double x0, double y0, double x1, double y1) {
  const CellIndex lo = map.cell_of(x0, y0);
  const CellIndex hi = map.cell_of(x1, y1);
  return {lo, hi.x - lo.x + 1, hi.y - lo.y + 1};
}

std::vector<MlsPatch> patches_at(const MlsMap& map, double x, double y) {
  return map.patches(map.cell_of(x, y));
}

TEST(MlsMap, FlatFloorGivesOneHorizontalPatchPerCell) {
  MlsMap map(static_scene_config());
  PointCloud cloud;
  test::add_plane(cloud, -2, 2, -2, 2, 0.0);
  map.insert_scan(cloud, {0, 0, 1.5});
  EXPECT_EQ(map.occupied_cell_count(), 40U * 40U);
  EXPECT_EQ(map.patch_count(), 40U * 40U);
  for (double x = -1.95; x < 2; x += 0.1)
    for (double y = -1.95; y < 2; y += 0.1) {
      const auto patches = patches_at(map, x, y);
      ASSERT_EQ(patches.size(), 1U) << x << ' ' << y;
      EXPECT_FALSE(patches[0].vertical());
      EXPECT_NEAR(patches[0].mean, 0.0, 0.005);
      // Many points: far more certain than one at that range.
      const double one = map.config().sigma_base + map.config().sigma_per_metre * std::hypot(x, y, 1.5);
      EXPECT_LT(patches[0].variance, one * one / 2.0);
    }
}

TEST(MlsMap, VarianceGrowsWithRange) {
  MlsMap map(static_scene_config());
  map.insert_scan({{1.05, 0.05, 0.0}, {20.05, 0.05, 0.0}}, {0, 0, 0});
  EXPECT_LT(patches_at(map, 1.05, 0.05)[0].variance, patches_at(map, 20.05, 0.05)[0].variance);
}

TEST(MlsMap, FloorSeenFromAfarScattersWithoutStandingUp) {
  // A moving sensor's tilt error scatters the floor it sees at 10 m over about 0.13 m (the poses of the
  // scans that saw it disagree): one horizontal patch. The same spread seen from 1 m is a step or a
  // thin obstacle: vertical. More than twice tau is vertical from anywhere.
  MlsMap map;
  const auto cell_after = [&](double x, const Eigen::Vector3d& origin,
                              std::initializer_list<double> heights) {
    for (const double z : heights)
      map.insert_scan({{x, 0.05, z}}, origin);
    return patches_at(map, x, 0.05);
  };
  const auto far = cell_after(10.05, {0, 0, 1.4}, {-0.02, 0.11, 0.03, 0.09});
  ASSERT_EQ(far.size(), 1U);
  EXPECT_FALSE(far[0].vertical());
  EXPECT_NEAR(far[0].mean, 0.05, 0.03);
  const auto near = cell_after(1.05, {0, 0, 0.3}, {-0.02, 0.11});
  ASSERT_EQ(near.size(), 1U);
  EXPECT_TRUE(near[0].vertical());
  const auto wall = cell_after(12.05, {0, 0, 1.4}, {0.0, 0.25});
  ASSERT_EQ(wall.size(), 1U);
  EXPECT_TRUE(wall[0].vertical());
}

TEST(MlsMap, FloorMappedNearStaysFloorWhenSeenAgainFromAfar) {
  // A hallway's floor mapped from 2 m, then seen again from 30 m down the hallway by scans whose tilt is
  // off by up to half a degree: its points scatter 0.25 m either way. They are the floor seen badly,
  // not a step (they had cut the hallway with vertical patches). Something higher than the far points'
  // own scatter still stands up, and so does a near scan's step.
  MlsMap map;
  const double x = 30.05;
  for (const double z : {0.0, 0.005, -0.005, 0.0})
    map.insert_scan({{x, 0.05, z}}, {x - 2.0, 0, 0.7});
  for (const double z : {0.25, -0.22, 0.18, -0.25, 0.2})
    map.insert_scan({{x, 0.05, z}}, {0, 0, 0.7});
  auto patches = patches_at(map, x, 0.05);
  ASSERT_EQ(patches.size(), 1U);
  EXPECT_FALSE(patches[0].vertical());
  EXPECT_NEAR(patches[0].mean, 0.0, 0.01);         // far points barely move what near ones measured
  map.insert_scan({{x, 0.05, 0.5}}, {0, 0, 0.7});  // a box on the floor, seen from afar
  patches = patches_at(map, x, 0.05);
  ASSERT_EQ(patches.size(), 1U);
  EXPECT_TRUE(patches[0].vertical());

  const double y = 1.05;  // the same scatter from near: a step
  for (const double z : {0.0, 0.005, 0.15})
    map.insert_scan({{x, y, z}}, {x - 2.0, y, 0.7});
  EXPECT_TRUE(patches_at(map, x, y)[0].vertical());
}

TEST(MlsMap, GapRuleSplitsAndMergesPatches) {
  MlsMap map(static_scene_config(1.0));
  map.insert_scan({{0.05, 0.05, 0.0}, {0.05, 0.05, 1.5}}, {0, 0, 3});
  ASSERT_EQ(patches_at(map, 0.05, 0.05).size(), 2U);  // 1.5 m apart: two surfaces
  map.insert_scan({{0.05, 0.05, 0.4}}, {0, 0, 3});
  auto patches = patches_at(map, 0.05, 0.05);
  ASSERT_EQ(patches.size(), 2U);
  EXPECT_TRUE(patches[0].vertical());  // 0 .. 0.4 spans more than tau: a structure
  EXPECT_NEAR(patches[0].depth, 0.4, 1e-6);
  map.insert_scan({{0.05, 0.05, 0.9}}, {0, 0, 3});  // now less than gamma below 1.5: one column
  patches = patches_at(map, 0.05, 0.05);
  ASSERT_EQ(patches.size(), 1U);
  EXPECT_NEAR(patches[0].top(), 1.5, 1e-6);
  EXPECT_NEAR(patches[0].bottom(), 0.0, 1e-6);
}

TEST(MlsMap, WallIsAVerticalPatchAndOccupied) {
  MlsMap map(static_scene_config());
  PointCloud cloud;
  test::add_plane(cloud, -2, 2.5, -2, 2, 0.0);
  test::add_vertical_face(cloud, 2.02, -2, 2.02, 2, 0.0, 2.0);
  map.insert_scan(cloud, {0, 0, 1.0});
  const auto wall = patches_at(map, 2.02, 0.05);
  ASSERT_EQ(wall.size(), 1U);
  EXPECT_TRUE(wall[0].vertical());
  EXPECT_GT(wall[0].depth, 1.8F);
  const DrivableMap drivable =
      compute_drivable_map(map, TraversabilityConfig{}, {0, 0, 0}, region_of(map, -2, -2, 2.5, 2));
  ASSERT_TRUE(drivable.start_found);
  EXPECT_EQ(drivable.grid.at_position(2.02, 0.05), Occupancy::occupied);
  EXPECT_EQ(drivable.grid.at_position(1.5, 0.05), Occupancy::free);
  // Behind the wall: floor at the robot's level, not reached; whether a way leads there is the planner's
  // question.
  EXPECT_EQ(drivable.grid.at_position(2.3, 0.05), Occupancy::free);
  EXPECT_EQ(drivable.connected[drivable.grid.index(drivable.grid.cell_of({2.3, 0.05}))], 0);
}

// A slab seen from below and from above (a bridge deck, an upper floor) is one vertical patch from its
// underside to its top. Its top is a surface: points from afar scatter about it, and it must stay where
// they are, not climb to the highest of them, or the deck's cells stand as steps among their neighbours.
TEST(MlsMap, ASlabsTopIsItsSurfaceNotTheHighestNoiseSeenOnIt) {
  MlsMap map(static_scene_config());
  PointCloud top;
  test::add_plane(top, 0, 0.1, 0, 0.1, 1.5, 0.02);
  map.insert_scan(top, {0, 0, 2.5});
  map.insert_scan(PointCloud{{0.05, 0.05, 1.2}}, {0, 0, 0.5});  // the underside, from below
  PointCloud far;  // the top seen again from 10 m away, scattered 5 cm
  test::add_surface(
      far, 0, 0.1, 0, 0.1, [](double, double) { return 1.5; }, 0.005, 0.05, 3);
  map.insert_scan(far, {10, 0, 2.5});
  const auto slab = patches_at(map, 0.05, 0.05);
  ASSERT_EQ(slab.size(), 1U);
  EXPECT_TRUE(slab[0].vertical());
  EXPECT_NEAR(slab[0].top(), 1.5F, 0.02F) << "the highest of " << far.size() << " points is far above";
  EXPECT_NEAR(slab[0].bottom(), 1.2F, 0.01F);
  // What stands well above the top still raises it: a wall is as high as its highest point.
  map.insert_scan(PointCloud{{0.05, 0.05, 2.0}}, {0, 0, 2.5});
  EXPECT_NEAR(patches_at(map, 0.05, 0.05)[0].top(), 2.0F, 1e-4F);
}

TEST(MlsMap, FloorUnderATableIsDrivableForALowRobotOnly) {
  // gamma at the low robot's height, so the table top (0.75 m) is a surface of its own above the floor.
  MlsMap map(static_scene_config(0.5));
  PointCloud cloud;
  test::add_plane(cloud, -2, 3, -2, 2, 0.0);
  test::add_plane(cloud, 1, 2, -0.5, 0.5, 0.75);
  map.insert_scan(cloud, {0, 0, 0.3});
  const auto under = patches_at(map, 1.55, 0.05);
  ASSERT_EQ(under.size(), 2U);
  EXPECT_NEAR(under[0].mean, 0.0, 0.01);
  EXPECT_NEAR(under[1].mean, 0.75, 0.01);

  TraversabilityConfig low;
  low.robot_height = 0.5;
  TraversabilityConfig tall;
  tall.robot_height = 1.2;
  const CellRegion region = region_of(map, -2, -2, 3, 2);
  const DrivableMap low_map = compute_drivable_map(map, low, {0, 0, 0}, region);
  const DrivableMap tall_map = compute_drivable_map(map, tall, {0, 0, 0}, region);
  EXPECT_EQ(low_map.grid.at_position(1.55, 0.05), Occupancy::free);
  EXPECT_EQ(tall_map.grid.at_position(1.55, 0.05), Occupancy::occupied);
  EXPECT_EQ(tall_map.grid.at_position(0.55, 0.05), Occupancy::free);
  EXPECT_EQ(tall_map.grid.at_position(2.55, 0.05), Occupancy::free);  // around the table
}

PointCloud ramp_scene(double angle_degrees) {
  const double gradient = std::tan(angle_degrees * std::numbers::pi / 180.0);
  PointCloud cloud;
  test::add_surface(cloud, -2, 5, -1.5, 1.5, [gradient](double x, double) {
    return std::clamp(x - 1.0, 0.0, 2.0) * gradient;  // flat, 2 m of ramp, flat again
  });
  return cloud;
}

TEST(MlsMap, RampWithinLimitsIsDrivable) {
  MlsMap map(static_scene_config());
  map.insert_scan(ramp_scene(8.0), {0, 0, 1});
  const DrivableMap drivable =
      compute_drivable_map(map, TraversabilityConfig{}, {0, 0, 0}, region_of(map, -2, -1.5, 5, 1.5));
  EXPECT_EQ(drivable.grid.at_position(2.05, 0.05), Occupancy::free);  // on the ramp
  EXPECT_EQ(drivable.grid.at_position(4.05, 0.05), Occupancy::free);  // on top
  const CellIndex top = map.cell_of(4.05, 0.05);
  const std::size_t index = static_cast<std::size_t>(top.y - map.cell_of(-2, -1.5).y) *
                                static_cast<std::size_t>(drivable.grid.width) +
                            static_cast<std::size_t>(top.x - map.cell_of(-2, -1.5).x);
  EXPECT_NEAR(drivable.grid.surface_height[index], 2.0 * std::tan(8.0 * std::numbers::pi / 180.0), 0.02);
}

TEST(MlsMap, TooSteepRampIsNotDrivable) {
  MlsMap map(static_scene_config());
  map.insert_scan(ramp_scene(25.0), {0, 0, 1});
  const DrivableMap drivable =
      compute_drivable_map(map, TraversabilityConfig{}, {0, 0, 0}, region_of(map, -2, -1.5, 5, 1.5));
  EXPECT_EQ(drivable.grid.at_position(0.05, 0.05), Occupancy::free);
  EXPECT_EQ(drivable.grid.at_position(2.05, 0.05), Occupancy::occupied);
  EXPECT_EQ(drivable.grid.at_position(4.05, 0.05), Occupancy::occupied);
}

TEST(MlsMap, StairsAreNotDrivableForTheWheelchair) {
  MlsMap map(static_scene_config());
  PointCloud cloud;
  test::add_surface(cloud, -2, 4, -1.5, 1.5, [](double x, double) {
    return x < 1.0 ? 0.0 : 0.17 * std::min(5.0, std::floor((x - 1.0) / 0.3) + 1.0);
  });
  map.insert_scan(cloud, {0, 0, 1});
  const DrivableMap drivable =
      compute_drivable_map(map, TraversabilityConfig{}, {0, 0, 0}, region_of(map, -2, -1.5, 4, 1.5));
  EXPECT_EQ(drivable.grid.at_position(0.55, 0.05), Occupancy::free);
  EXPECT_EQ(drivable.grid.at_position(1.15, 0.05), Occupancy::occupied);  // first tread
  EXPECT_EQ(drivable.grid.at_position(3.05, 0.05), Occupancy::occupied);  // landing
}

TEST(MlsMap, BridgeOverRoadGivesTwoLevelsEachDrivableFromItsOwn) {
  MlsMap map(static_scene_config());
  PointCloud road;
  test::add_plane(road, -6, 6, -1.5, 1.5, 0.0);
  PointCloud deck;
  test::add_plane(deck, -1.5, 1.5, -5, 5, 5.0);
  map.insert_scan(road, {4, 0, 1});
  map.insert_scan(deck, {0, 3.5, 6});
  const auto both = patches_at(map, 0.05, 0.05);
  ASSERT_EQ(both.size(), 2U);
  EXPECT_NEAR(both[0].mean, 0.0, 0.01);
  EXPECT_NEAR(both[1].mean, 5.0, 0.01);

  const CellRegion region = region_of(map, -6, -5, 6, 5);
  const DrivableMap on_road = compute_drivable_map(map, TraversabilityConfig{}, {4, 0, 0}, region);
  ASSERT_TRUE(on_road.start_found);
  EXPECT_EQ(on_road.grid.at_position(0.05, 0.05), Occupancy::free);     // under the deck
  EXPECT_EQ(on_road.grid.at_position(-4.05, 0.05), Occupancy::free);    // the far side
  EXPECT_EQ(on_road.grid.at_position(0.05, 3.55), Occupancy::unknown);  // only the deck, overhead, seen

  const DrivableMap on_deck = compute_drivable_map(map, TraversabilityConfig{}, {0, 3.5, 5}, region);
  ASSERT_TRUE(on_deck.start_found);
  EXPECT_EQ(on_deck.grid.at_position(0.05, 0.05), Occupancy::free);  // the deck over the road
  EXPECT_EQ(on_deck.grid.at_position(0.05, -4.05), Occupancy::free);
  EXPECT_EQ(on_deck.grid.at_position(4.05, 0.05), Occupancy::occupied);  // the road below
  const CellIndex centre = map.cell_of(0.05, 0.05);
  const std::size_t index =
      static_cast<std::size_t>(centre.y - region.min.y) * static_cast<std::size_t>(region.width) +
      static_cast<std::size_t>(centre.x - region.min.x);
  EXPECT_NEAR(on_deck.grid.surface_height[index], 5.0, 0.01);
  EXPECT_NEAR(on_road.grid.surface_height[index], 0.0, 0.01);
}

/// A room-sized scene seen from (0, 0, 1): floor, a static wall at x = 5.5 and, optionally, a person
/// standing at x = 2..2.4 who hides what lies behind them.
PointCloud person_scan(bool with_person) {
  const Eigen::Vector3d sensor(0, 0, 1.0);
  const Eigen::Vector3d person_lo(2.0, -0.2, 0.0);
  const Eigen::Vector3d person_hi(2.4, 0.2, 1.8);
  PointCloud background;
  test::add_plane(background, -1, 5.5, -3, 3, 0.0);
  test::add_vertical_face(background, 5.52, -3, 5.52, 3, 0.0, 2.5);
  if (!with_person)
    return background;
  PointCloud scan;
  for (const Eigen::Vector3d& p : background)
    if (!test::segment_hits_box(sensor, p, person_lo - Eigen::Vector3d::Constant(0.01),
                                person_hi + Eigen::Vector3d::Constant(0.01)))
      scan.push_back(p);
  test::add_vertical_face(scan, 2.0, -0.2, 2.0, 0.2, 0.0, 1.8, 0.02);  // front
  test::add_vertical_face(scan, 2.0, -0.2, 2.4, -0.2, 0.0, 1.8, 0.02);
  test::add_vertical_face(scan, 2.0, 0.2, 2.4, 0.2, 0.0, 1.8, 0.02);
  return scan;
}

bool has_vertical_patch(const MlsMap& map, double x, double y) {
  const auto patches = patches_at(map, x, y);
  return std::any_of(patches.begin(), patches.end(), [](const MlsPatch& p) { return p.vertical(); });
}

TEST(MlsMap, PersonWhoWalksAwayFadesOutWhileTheWallStays) {
  MlsMap map;  // default config: free-space clearing on
  const Eigen::Vector3d sensor(0, 0, 1.0);
  for (int i = 0; i < 3; ++i)
    map.insert_scan(person_scan(true), sensor);
  ASSERT_TRUE(has_vertical_patch(map, 2.05, 0.05));
  ASSERT_TRUE(has_vertical_patch(map, 5.55, 1.05));  // the wall beside the person's shadow

  std::size_t cleared = 0;
  for (int i = 0; i < 3; ++i)
    cleared += map.insert_scan(person_scan(false), sensor).patches_cleared;
  EXPECT_GT(cleared, 0U);
  for (double x = 2.05; x < 2.4; x += 0.1)
    for (double y = -0.15; y < 0.2; y += 0.1) {
      EXPECT_FALSE(has_vertical_patch(map, x, y)) << x << ' ' << y;
      const auto floor = patches_at(map, x, y);  // the floor the person stood on, seen again
      ASSERT_EQ(floor.size(), 1U);
      EXPECT_NEAR(floor[0].mean, 0.0, 0.02);
    }
  for (double y = -2.95; y < 3; y += 0.1)
    EXPECT_TRUE(has_vertical_patch(map, 5.55, y)) << y;  // hit every time: never fades
  for (double x = -0.95; x < 5.3; x += 0.5)
    EXPECT_EQ(patches_at(map, x, 1.05).size(), 1U) << x;  // the floor is not cleared by grazing rays
}

// The rays walk cell by cell and look a tile up only when they step out of one: the same scene turned to
// every side (and diagonally) clears the person across the tile boundaries at x = 0 and y = 0, where the
// cells step into negative tiles.
TEST(MlsMap, APersonFadesOutOnEverySideAcrossTileBoundaries) {
  const Eigen::Vector3d sensor(0, 0, 1.0);
  for (const double degrees : {90.0, 135.0, 180.0, 270.0, 315.0}) {
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const auto turned = [&](const PointCloud& points) {
      PointCloud out;
      for (const Eigen::Vector3d& p : points)
        out.push_back(turn * p);
      return out;
    };
    MlsMap map;
    for (int i = 0; i < 3; ++i)
      map.insert_scan(turned(person_scan(true)), sensor);
    // Turned, the front face at x = 2 falls on either side of its cells' edge.
    bool standing = false;
    for (const double y : {-0.15, -0.05, 0.05, 0.15})
      for (const double x : {1.95, 2.05}) {
        const Eigen::Vector3d at = turn * Eigen::Vector3d(x, y, 0.0);
        standing = standing || has_vertical_patch(map, at.x(), at.y());
      }
    ASSERT_TRUE(standing) << degrees;
    for (int i = 0; i < 3; ++i)
      map.insert_scan(turned(person_scan(false)), sensor);
    for (double x = 2.05; x < 2.4; x += 0.1)
      for (double y = -0.15; y < 0.2; y += 0.1) {
        const Eigen::Vector3d at = turn * Eigen::Vector3d(x, y, 0.0);
        EXPECT_FALSE(has_vertical_patch(map, at.x(), at.y())) << degrees << ": " << x << ' ' << y;
      }
    const Eigen::Vector3d wall = turn * Eigen::Vector3d(5.55, 1.05, 0.0);
    EXPECT_TRUE(has_vertical_patch(map, wall.x(), wall.y())) << degrees;
  }
}

TEST(MlsMap, TileVersionsTrackChanges) {
  MlsMap map(static_scene_config());
  EXPECT_EQ(map.version(), 0U);
  PointCloud here;
  test::add_plane(here, 0, 1, 0, 1, 0.0);
  map.insert_scan(here, {0, 0, 1});
  EXPECT_EQ(map.version(), 1U);
  ASSERT_EQ(map.tiles_changed_since(0).size(), 1U);
  EXPECT_EQ(map.tiles_changed_since(0)[0], (TileIndex{0, 0}));
  PointCloud far;
  test::add_plane(far, -20, -19.5, 30, 31, 0.0);  // within one tile
  map.insert_scan(far, {-20, 30, 1});
  const auto changed = map.tiles_changed_since(1);
  ASSERT_EQ(changed.size(), 1U);
  EXPECT_EQ(changed[0], (MlsMap::tile_of(map.cell_of(-19.7, 30.5))));
  EXPECT_EQ(map.tiles_changed_since(0).size(), 2U);
  EXPECT_TRUE(map.tiles_changed_since(2).empty());
}

TEST(MlsMap, NegativeCoordinatesMapToTheirOwnCells) {
  MlsMap map(static_scene_config());
  map.insert_scan({{-0.05, -0.05, 0.0}, {0.05, 0.05, 0.3}}, {0, 0, 1});
  EXPECT_EQ(map.cell_of(-0.05, -0.05), (CellIndex{-1, -1}));
  EXPECT_EQ(MlsMap::tile_of({-1, -1}), (TileIndex{-1, -1}));
  EXPECT_NEAR(patches_at(map, -0.05, -0.05)[0].mean, 0.0, 1e-6);
  EXPECT_NEAR(patches_at(map, 0.05, 0.05)[0].mean, 0.3, 1e-6);
  EXPECT_EQ(map.tile_count(), 2U);
}

TEST(MlsMap, DropsPointsItCannotUse) {
  MlsMap map;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const MlsInsertStats stats =
      map.insert_scan({{nan, 0, 0}, {1e300, 0, 0}, {0.01, 0.01, 1.0}, {1.05, 0.05, 0.0}}, {0, 0, 1});
  EXPECT_EQ(stats.points_dropped, 3U);  // not finite, absurdly far, closer than min_range
  EXPECT_EQ(map.patch_count(), 1U);
}

TEST(MlsMap, MemoryPerOccupiedCellStaysSmall) {
  MlsMap map(static_scene_config());
  PointCloud cloud;
  test::add_plane(cloud, -12.8, 12.8, -12.8, 12.8, 0.0, 0.05);
  map.insert_scan(cloud, {0, 0, 1});
  const double per_cell =
      static_cast<double>(map.memory_bytes()) / static_cast<double>(map.occupied_cell_count());
  EXPECT_LT(per_cell, 40.0);
}

}  // namespace
}  // namespace strata

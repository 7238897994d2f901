// The ground the robot drives over (MlsMap::mark_driven): the robot never strands itself on a map that does
// not show the ground it stands on (issue 21).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/mls/drivable_map.hpp"
#include "core/mls/mls_map.hpp"
#include "core/navigation/patch_graph_planner.hpp"
#include "tests/support/navigation_scenes.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata {
namespace {

MlsConfig scene_config() {
  MlsConfig config;
  config.free_space_ray_stride = 0;  // hand-made scenes have no occlusion
  return config;
}

CellRegion around(const MlsMap& map, double half) {
  const CellIndex lo = map.cell_of(-half, -half);
  const CellIndex hi = map.cell_of(half, half);
  return {lo, hi.x - lo.x + 1, hi.y - lo.y + 1};
}

Occupancy at(const DrivableMap& drivable, double x, double y) {
  return drivable.grid.at_position(x, y);
}

bool connected_at(const DrivableMap& drivable, double x, double y) {
  return drivable.connected[drivable.grid.index(drivable.grid.cell_of({x, y}))] != 0;
}

/// A car's lidar 2.15 m up sees flat ground only from 3.7 m out: floor in an annulus, nothing nearer.
MlsMap blind_circle_scene() {
  MlsMap map(scene_config());
  PointCloud cloud;
  for (double x = -8.0; x < 8.0; x += 0.04)
    for (double y = -8.0; y < 8.0; y += 0.04)
      if (std::hypot(x, y) >= 3.7)
        cloud.emplace_back(x, y, 0.0);
  map.insert_scan(cloud, {0, 0, 2.15});
  return map;
}

TEST(DrivenGround, TheRobotStandsOnGroundItsScannerNeverSaw) {
  MlsMap map = blind_circle_scene();
  const TraversabilityConfig traversability;
  const Eigen::Vector3d robot(0, 0, 0);
  const DrivableMap before = compute_drivable_map(map, traversability, robot, around(map, 8));
  EXPECT_FALSE(before.start_found);
  EXPECT_EQ(before.free_cells, 0U) << "no level known: nothing free";

  const std::uint64_t version = map.version();
  const std::size_t marked = map.mark_driven(robot);
  // The cells whose centres lie within 0.3 m: about pi * 3^2 of them.
  EXPECT_GT(marked, 24U);
  EXPECT_LT(marked, 34U);
  EXPECT_EQ(map.version(), version + 1);
  const std::vector<MlsPatch> under = map.patches(map.cell_of(0.05, 0.05));
  ASSERT_EQ(under.size(), 1U);
  EXPECT_TRUE(under[0].driven());
  EXPECT_FALSE(under[0].vertical());
  EXPECT_FLOAT_EQ(under[0].mean, 0.0F);
  EXPECT_TRUE(map.patches(map.cell_of(0.45, 0.0)).empty()) << "beyond the radius: still unseen";

  const DrivableMap after = compute_drivable_map(map, traversability, robot, around(map, 8));
  ASSERT_TRUE(after.start_found);
  EXPECT_EQ(at(after, 0.05, 0.05), Occupancy::free);
  EXPECT_TRUE(connected_at(after, 0.05, 0.05));
  // The level is known now, so the seen floor at that level is free (not connected: 3.4 m unseen between).
  EXPECT_EQ(at(after, 5.0, 0.0), Occupancy::free);
  EXPECT_FALSE(connected_at(after, 5.0, 0.0));
  EXPECT_EQ(at(after, 2.0, 0.0), Occupancy::unknown) << "the blind circle stays unknown";
  EXPECT_GT(after.free_cells, 15000U);
}

TEST(DrivenGround, MarksTheFloorItFindsAndChangesNothingTwice) {
  MlsMap map(scene_config());
  PointCloud cloud;
  test::add_plane(cloud, -1, 1, -1, 1, 0.03);
  map.insert_scan(cloud, {0, 0, 1});
  const std::size_t patches = map.patch_count();
  const std::uint64_t version = map.version();

  EXPECT_GT(map.mark_driven({0, 0, 0}), 24U);
  EXPECT_EQ(map.patch_count(), patches) << "the measured floor is what it stands on: no new patches";
  EXPECT_EQ(map.version(), version + 1);
  EXPECT_FALSE(map.tiles_changed_since(version).empty());
  const std::vector<MlsPatch> under = map.patches(map.cell_of(0.05, -0.05));
  ASSERT_EQ(under.size(), 1U);
  EXPECT_TRUE(under[0].driven());
  EXPECT_NEAR(under[0].mean, 0.03, 0.01) << "the measured height stays";
  EXPECT_FALSE(under[0].on_track()) << "beside the robot's centre";
  EXPECT_TRUE(map.patches(map.cell_of(0.05, 0.05))[0].on_track()) << "under it";
  EXPECT_FALSE(map.patches(map.cell_of(0.55, 0.0))[0].driven());

  EXPECT_EQ(map.mark_driven({0.01, 0, 0.02}), 0U) << "marked already";
  EXPECT_EQ(map.version(), version + 1) << "nothing changed, no new version (no tiles to re-encode)";
  EXPECT_EQ(map.mark_driven({0, 0, std::numeric_limits<double>::quiet_NaN()}), 0U);
}

TEST(DrivenGround, AScanMarksWhereTheRobotStoodUnderItsOwnVersion) {
  MlsMap map(scene_config());
  PointCloud far;
  test::add_plane(far, 4, 6, -1, 1, 0.0);
  const MlsInsertStats stats = map.insert_scan(far, {0, 0, 1}, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(map.version(), 1U) << "one scan, one version";
  EXPECT_GT(stats.driven_cells, 24U);
  EXPECT_EQ(map.find_tile(map.tile_of(map.cell_of(0.05, 0.05)))->version, 1U);

  // A scan of nothing usable (a sensor fault) changes nothing, the ground under the robot included.
  const std::size_t patches = map.patch_count();
  const MlsInsertStats nothing = map.insert_scan({{std::numeric_limits<double>::quiet_NaN(), 0, 0}},
                                                 {0, 0, 1}, Eigen::Vector3d(3, 0, 0));
  EXPECT_EQ(nothing.driven_cells, 0U);
  EXPECT_EQ(map.patch_count(), patches);
}

// Issue 58: at 5x real time the campus demo mapped one scan in six, footprints 0.5-0.7 m apart, and the
// bridge deck's seam with the plateau kept, in cells between two footprints, only the plateau's face seen
// from the road below: a wall across the way back. The ground between two scans' footprints bore the
// robot too; a jump farther than driven_stride (a relocalization) marks nothing between.
TEST(DrivenGround, TheWayBetweenTwoScansIsDrivenAJumpIsNot) {
  const auto deck_with_a_seam = [] {
    MlsMap map(scene_config());
    PointCloud deck;
    test::add_plane(deck, -1, 1.95, -1, 1, 3.0);
    test::add_plane(deck, 2.25, 2.95, -1, 1, 3.0);
    test::add_plane(deck, 3.25, 6, -1, 1, 3.0);
    map.insert_scan(deck, {2, 0, 4});
    PointCloud below;  // x = 2.0-2.1: a face from the road up to 2.4 m; x = 3.0-3.1: the underside
    for (double y = -0.95; y < 1.0; y += 0.1) {
      for (double z = 0.0; z < 2.4; z += 0.05)
        below.emplace_back(2.05, y, z);
      below.emplace_back(3.05, y, 2.7);
    }
    map.insert_scan(below, {-3, 0, 1});
    return map;
  };
  const auto top_driven = [](const MlsMap& map, double x, double y) {
    const std::vector<MlsPatch> patches = map.patches(map.cell_of(x, y));
    return !patches.empty() && patches.back().driven() && std::abs(patches.back().top() - 3.0F) < 0.05F;
  };
  MlsMap map = deck_with_a_seam();
  ASSERT_FALSE(top_driven(map, 2.05, 0.0));
  ASSERT_FALSE(top_driven(map, 3.05, 0.0));
  PointCloud far;
  test::add_plane(far, 4, 6, -1, 1, 3.0);
  for (const double x : {1.4, 2.7, 3.6})
    map.insert_scan(far, {x, 0, 4}, Eigen::Vector3d(x, 0, 3));
  for (const double y : {-0.2, 0.0, 0.2}) {
    EXPECT_TRUE(top_driven(map, 2.05, y)) << "the seam at y = " << y << ", between the footprints";
    EXPECT_TRUE(top_driven(map, 3.05, y)) << "the underside at y = " << y << ", between the footprints";
  }
  EXPECT_TRUE(map.patches(map.cell_of(3.05, 0.0)).back().vertical())
      << "from the underside up to the deck, as a point on the deck would make it";
  EXPECT_FALSE(top_driven(map, 2.05, 0.45)) << "beyond the footprint's radius of the way";

  MlsMap jumped = deck_with_a_seam();
  jumped.insert_scan(far, {0.0, 0, 4}, Eigen::Vector3d(0.0, 0, 3));
  jumped.insert_scan(far, {4.1, 0, 4}, Eigen::Vector3d(4.1, 0, 3));
  EXPECT_FALSE(top_driven(jumped, 2.05, 0.0)) << "4.1 m between two scans is a jump, not a drive";

  // The same two scans with the places the robot passed between them (scans the mapping dropped).
  MlsMap passed = deck_with_a_seam();
  passed.insert_scan(far, {0.0, 0, 4}, Eigen::Vector3d(0.0, 0, 3));
  const std::uint64_t before = passed.version();
  EXPECT_GT(passed.mark_passed({1.4, 0, 3}), 0U);
  EXPECT_EQ(passed.version(), before + 1);
  EXPECT_GT(passed.mark_passed({2.7, 0, 3}), 0U);
  EXPECT_EQ(passed.mark_passed({std::numeric_limits<double>::quiet_NaN(), 0, 3}), 0U);
  passed.insert_scan(far, {4.1, 0, 4}, Eigen::Vector3d(4.1, 0, 3));
  for (const double x : {0.7, 2.05, 3.05, 3.5})
    EXPECT_TRUE(top_driven(passed, x, 0.0)) << "x = " << x << ": driven through the places passed";
}

TEST(DrivenGround, TheRobotsOwnBodyIsNoObstacleWhereItStands) {
  // A lidar on a car's roof (2.15 m) sees the bonnet 0.8 m up around it, and no ground within 3.7 m: the
  // bonnet's patches are the car itself, gone once the ground it stands on is marked; beyond the
  // footprint, what the scan saw stays.
  MlsMap map(scene_config());
  PointCloud scan;
  test::add_plane(scan, -0.4, 0.4, -0.4, 0.4, 0.8);  // the bonnet, a little wider than the footprint
  test::add_plane(scan, 4, 6, -1, 1, 0.0);           // the road far out
  map.insert_scan(scan, {0, 0, 2.15}, Eigen::Vector3d(0, 0, 0));
  const std::vector<MlsPatch> under = map.patches(map.cell_of(0.05, 0.05));
  ASSERT_EQ(under.size(), 1U);
  EXPECT_TRUE(under[0].driven());
  EXPECT_FLOAT_EQ(under[0].mean, 0.0F);
  EXPECT_EQ(map.patches(map.cell_of(0.35, 0.35)).size(), 1U) << "outside the footprint: kept";
  EXPECT_FALSE(map.patches(map.cell_of(0.35, 0.35))[0].driven());
}

TEST(DrivenGround, TheUnseenFootprintTakesTheHeightOfTheGroundSeenInIt) {
  // The pose's height is 12 cm above the floor the scanner saw in part of the footprint: the unseen rest
  // is put at the floor's height, not the pose's, or the footprint would be a step the robot cannot climb.
  MlsMap map(scene_config());
  PointCloud floor;
  test::add_plane(floor, 0.0, 1.0, -1.0, 1.0, -0.12);
  map.insert_scan(floor, {0, 0, 1});
  map.mark_driven({0, 0, 0});
  EXPECT_NEAR(map.patches(map.cell_of(-0.15, 0.05))[0].mean, -0.12, 0.01) << "unseen, put at the floor";
  EXPECT_NEAR(map.patches(map.cell_of(0.15, 0.05))[0].mean, -0.12, 0.01) << "seen";
}

TEST(DrivenGround, LeavesWallsAndLowOverhangsAsTheyWereMeasured) {
  MlsMap map(scene_config());
  PointCloud cloud;
  test::add_plane(cloud, -1, 1, -1, 1, 0.0);
  test::add_vertical_face(cloud, 0.21, -1, 0.21, 1, 0.0, 2.0);  // a wall 0.2 m from the robot's centre
  test::add_plane(cloud, -1, -0.15, -0.1, 0.1, 0.6);            // a shelf 0.6 m up, its edge 0.15 m away
  map.insert_scan(cloud, {0, 0, 1});
  const MlsMap measured = [&] {
    MlsMap copy(scene_config());
    copy.insert_scan(cloud, {0, 0, 1});
    return copy;
  }();

  map.mark_driven({0, 0, 0});
  EXPECT_EQ(map.patch_count(), measured.patch_count());
  const std::vector<MlsPatch> wall = map.patches(map.cell_of(0.25, 0.0));
  ASSERT_EQ(wall.size(), 1U);
  EXPECT_TRUE(wall[0].vertical());
  EXPECT_FALSE(wall[0].driven()) << "a wall is no ground to stand on";
  // Under the shelf the floor and the shelf merged into one structure (gap rule): not the robot's ground.
  for (const MlsPatch& patch : map.patches(map.cell_of(-0.25, 0.0)))
    EXPECT_FALSE(patch.driven());
  EXPECT_TRUE(map.patches(map.cell_of(0.05, 0.05))[0].driven()) << "the floor between is";
}

TEST(DrivenGround, DrivenGroundIsTraversableWhereTheMeasurementsSayNot) {
  // A low ceiling measured over the robot (a mast, a door frame seen from below at a grazing angle): the
  // classification says too little room; the robot is there, so there is room.
  MlsMap map(scene_config());
  PointCloud cloud;
  test::add_plane(cloud, -1, 1, -1, 1, 0.0);
  test::add_plane(cloud, -0.5, 0.5, -0.5, 0.5, 1.9);
  map.insert_scan(cloud, {0, 0, 1});
  TraversabilityConfig traversability;
  traversability.robot_height = 2.0;
  const SurfaceGrid before(map, around(map, 1), traversability);
  const auto [col, row] = before.local(map.cell_of(0.05, 0.05));
  EXPECT_FALSE(before.surfaces(before.cell(col, row))[0].traversable);

  map.mark_driven({0, 0, 0});
  const SurfaceGrid after(map, around(map, 1), traversability);
  const auto surfaces = after.surfaces(after.cell(col, row));
  ASSERT_EQ(surfaces.size(), 2U);
  EXPECT_TRUE(surfaces[0].driven);
  EXPECT_TRUE(surfaces[0].traversable);
  EXPECT_FALSE(surfaces[1].driven) << "the ceiling";
  const auto [edge_col, edge_row] = after.local(map.cell_of(0.45, 0.45));
  EXPECT_FALSE(after.surfaces(after.cell(edge_col, edge_row))[0].traversable) << "not driven there";
}

TEST(DrivenGround, TheTrackItDroveLeadsBackWhereItCameFrom) {
  // A joystick drive over ground the scanner never showed (a lidar's blind circle, a tilting scanner looking
  // the other way): 6 m of track, nothing else. The robot at its end can drive back along it.
  MlsMap map(scene_config());
  for (double x = 0.0; x <= 6.0; x += 0.1)
    map.mark_driven({x, 0.0, 0.02 * x});  // 2 % up
  const TraversabilityConfig traversability;
  const Eigen::Vector3d robot(6.0, 0.0, 0.12);
  const DrivableMap drivable = compute_drivable_map(map, traversability, robot, around(map, 7));
  ASSERT_TRUE(drivable.start_found);
  EXPECT_TRUE(connected_at(drivable, 0.05, 0.05));
  EXPECT_EQ(at(drivable, 3.0, 1.0), Occupancy::unknown);

  const PatchGraph graph = test::graph_of(map);
  const PatchPath back = plan_on_patches(graph, robot, {.x = 0.0, .y = 0.0});
  ASSERT_TRUE(back.found()) << describe(back.status);
  EXPECT_NEAR(back.length, 6.0, 0.2);
  EXPECT_EQ(plan_on_patches(graph, robot, {.x = 3.0, .y = 2.0}).status, PatchPlanStatus::goal_off_map)
      << "beside the track is still unseen";
}

// Issue 58: on the lidar demo's deck, cells of the robot's track lost their driven ground to rays that,
// with the pose's tilt a few tenths of a degree off, passed "through" the deck to points on it further on;
// a track cell gone closed the way back. Ground the robot stood on is not see-through.
TEST(DrivenGround, RaysThroughGroundTheRobotStoodOnDoNotClearIt) {
  MlsConfig config;
  config.free_space_ray_stride = 1;
  MlsMap map(config);
  PointCloud floor;
  test::add_plane(floor, -1, 1, -1, 2, 0.0);
  map.insert_scan(floor, {0, 0, 1});
  map.mark_driven({0.05, 0.05, 0.0});
  ASSERT_TRUE(map.patches(map.cell_of(0.05, 0.05))[0].driven());
  ASSERT_FALSE(map.patches(map.cell_of(0.05, 1.55))[0].driven());
  // Rays from 2 m west, 1 m up, to points 2 m east and 1 m below the floor: through the floor at x = 0,
  // where the robot stood (y = 0.05) and where it did not (y = 1.55).
  for (int i = 0; i < 20; ++i)
    for (const double y : {0.05, 1.55})
      map.insert_scan({{2.05, y, -1.0}}, {-1.95, y, 1.0});  // at height 0 in the middle of cell x 0-0.1
  const std::vector<MlsPatch> driven = map.patches(map.cell_of(0.05, 0.05));
  ASSERT_FALSE(driven.empty());
  EXPECT_TRUE(driven.front().driven());
  EXPECT_NEAR(driven.front().top(), 0.0, 0.01) << "the ground the robot stood on stays";
  const std::vector<MlsPatch> seen_only = map.patches(map.cell_of(0.05, 1.55));
  EXPECT_TRUE(seen_only.empty() || std::abs(seen_only.front().top()) > 0.01F) << "floor only seen is cleared";
}

// The track is the line of cells the robot's centre passed: unbroken between two scans' ground points
// (a cell of it missing between edges closes it, PatchGraph::passable), whatever the way's direction.
TEST(DrivenGround, TheTrackBetweenTwoScansSkipsNoCell) {
  // Places passed in a row (a way of several steps) and single ways in every direction.
  std::vector<std::vector<Eigen::Vector3d>> drives;
  std::vector<Eigen::Vector3d> along_the_deck;
  for (int i = 0; i <= 8; ++i)
    along_the_deck.emplace_back(83.6 + 0.3 * i, -28.75, 3.1);
  drives.push_back(along_the_deck);
  drives.push_back({{0.05, 0.05, 0.0}, {1.85, 0.05, 0.0}});
  drives.push_back({{0.03, 0.07, 0.0}, {1.83, 0.91, 0.0}});
  drives.push_back({{-0.31, 0.44, 0.0}, {0.52, -1.37, 0.0}});
  drives.push_back({{0.0, 0.0, 0.0}, {1.4, 1.4, 0.0}});
  drives.push_back({{12.95, 7.05, 1.0}, {11.15, 7.05, 1.0}});
  for (const std::vector<Eigen::Vector3d>& drive : drives) {
    MlsMap map(scene_config());
    for (const Eigen::Vector3d& place : drive)
      map.mark_passed(place);
    // Flood the track's cells from the first: 8-connected, it reaches the last.
    const CellIndex start = map.cell_of(drive.front().x(), drive.front().y());
    const CellIndex end = map.cell_of(drive.back().x(), drive.back().y());
    const auto on_track = [&](CellIndex cell) {
      const std::vector<MlsPatch> patches = map.patches(cell);
      return !patches.empty() && patches.front().on_track();
    };
    std::vector<CellIndex> open{start};
    std::vector<CellIndex> seen{start};
    bool reached = false;
    while (!open.empty() && !reached) {
      const CellIndex cell = open.back();
      open.pop_back();
      reached = cell.x == end.x && cell.y == end.y;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const CellIndex next{cell.x + dx, cell.y + dy};
          const bool known = std::any_of(seen.begin(), seen.end(),
                                         [&](CellIndex c) { return c.x == next.x && c.y == next.y; });
          if (!known && on_track(next)) {
            seen.push_back(next);
            open.push_back(next);
          }
        }
    }
    EXPECT_TRUE(reached) << "from " << drive.front().transpose() << " to " << drive.back().transpose();
    EXPECT_LE(seen.size(), 40U) << "a line, not the footprint";
  }
}

// Issue 58: the campus bridge deck was driven while the pose's height stood 0.1 m high, and seen beside the
// track only from far away, 0.1-0.15 m low: the 0.6 m of driven track lay a step above the deck around it,
// and the planner's 0.45 m radius found no room on it. The robot fitted there: it drives back along its
// track past lower ground, not past something that rises beside it.
TEST(DrivenGround, TheTrackLeadsBackPastLowerGroundNotPastAnObstacle) {
  // A box beside the track at `box_y` (none: 0), on the far views' ground.
  const auto deck = [](double box_y) {
    MlsMap map(scene_config());
    PointCloud cloud;
    test::add_plane(cloud, 0, 8, -0.3, 0.4, 3.0);   // where the robot drove, seen from near
    test::add_plane(cloud, 0, 8, -2.0, -0.3, 2.7);  // the far views, 0.3 m low
    test::add_plane(cloud, 0, 8, 0.4, 2.0, 2.7);
    if (box_y > 0.0)
      test::add_vertical_face(cloud, 4.0, box_y, 4.3, box_y, 2.7, 3.5);
    map.insert_scan(cloud, {4, 0, 4});
    for (double x = 0.05; x <= 7.96; x += 0.1)
      map.mark_driven({x, 0.05, 3.0});
    return map;
  };
  const Eigen::Vector3d robot(7.95, 0.05, 3.0);
  const PatchGoal back{.x = 0.55, .y = 0.05, .z = 3.0};

  const MlsMap open = deck(0.0);
  const PatchGraph graph = test::graph_of(open);
  const auto node_at = [&](double x, double y) { return *graph.locate(x, y, 3.0, 0.1); };
  EXPECT_LT(graph.clearance(node_at(4.05, 0.05)), graph.config().robot_radius) << "the far views are edges";
  EXPECT_TRUE(graph.on_track(node_at(4.05, 0.05)));
  EXPECT_TRUE(graph.passable(node_at(4.05, 0.05)));
  EXPECT_FALSE(graph.passable(node_at(4.05, 0.25))) << "driven, but the robot's centre was not there";
  const PatchPath path = plan_on_patches(graph, robot, back);
  ASSERT_TRUE(path.found()) << describe(path.status);
  EXPECT_NEAR(path.length, 7.4, 0.1);
  for (const Eigen::Vector3d& p : path.points)
    EXPECT_NEAR(p.z(), 3.0, 0.05);

  const MlsMap blocked = deck(0.45);  // 0.4 m from the track's middle, next to the driven band
  const PatchGraph boxed = test::graph_of(blocked);
  EXPECT_FALSE(boxed.passable(*boxed.locate(4.05, 0.05, 3.0, 0.1)));
  EXPECT_EQ(plan_on_patches(boxed, robot, back).status, PatchPlanStatus::no_path);

  // A box past a cell of the lower ground, 0.45 m from the track's middle, for a robot 0.5 m in radius:
  // what rises is looked for past the first edge.
  const MlsMap past_lower_ground = deck(0.55);
  const PatchGraphConfig wider{.robot_radius = 0.5};
  EXPECT_TRUE(plan_on_patches(test::graph_of(open, wider), robot, back).found());
  EXPECT_EQ(plan_on_patches(test::graph_of(past_lower_ground, wider), robot, back).status,
            PatchPlanStatus::no_path);
}

}  // namespace
}  // namespace strata

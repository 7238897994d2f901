// The surface rules in one place (SurfaceGrid): the drivable map the UI shows and the patch graph the
// planner searches step, stand and cross seams alike.
#include "core/mls/traversability.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include "core/mls/drivable_map.hpp"
#include "core/navigation/patch_graph.hpp"
#include "core/navigation/patch_graph_planner.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "tests/support/navigation_scenes.hpp"
#include "tests/support/seen_goals.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata {
namespace {

TEST(SurfaceGridRules, TheDrivableMapFillsWhatThePatchGraphLinks) {
  const MlsMap map = test::bridge_scene();
  const TraversabilityConfig traversability;
  const auto surfaces = test::surfaces_of(map, traversability);
  PatchGraphConfig graph_config;
  graph_config.traversability = traversability;
  graph_config.traversability.unseen_gaps.max_gap = 0.0;  // the same surfaces for both
  const PatchGraph graph(surfaces, map.resolution(), graph_config);

  for (const Eigen::Vector3d& robot : {Eigen::Vector3d(0, 22, 0), Eigen::Vector3d(-5, 0, 0)}) {
    const DrivableMap drivable = compute_drivable_map(map, *surfaces, traversability, robot);
    ASSERT_TRUE(drivable.start_found);
    // Everything the graph links to the robot's patch, whatever the robot's radius.
    const std::optional<PatchGraph::Node> start = graph.locate(
        robot.x(), robot.y(), robot.z(), traversability.start_tolerance, traversability.start_search_radius);
    ASSERT_TRUE(start.has_value());
    std::vector<std::uint8_t> linked(graph.node_count(), 0);
    std::vector<PatchGraph::Node> stack{*start};
    linked[*start] = 1;
    while (!stack.empty()) {
      const PatchGraph::Node node = stack.back();
      stack.pop_back();
      for (const PatchGraph::Node next : graph.neighbours(node))
        if (next != PatchGraph::kNone && linked[next] == 0) {
          linked[next] = 1;
          stack.push_back(next);
        }
    }
    std::set<std::pair<int, int>> linked_cells;
    for (PatchGraph::Node node = 0; node < graph.node_count(); ++node)
      if (linked[node] != 0)
        linked_cells.insert(graph.cell(node));
    std::size_t free = 0;
    for (int row = 0; row < drivable.grid.height; ++row)
      for (int col = 0; col < drivable.grid.width; ++col) {
        const bool is_connected = drivable.connected[drivable.grid.index({col, row})] != 0;
        free += is_connected ? 1 : 0;
        EXPECT_EQ(is_connected, linked_cells.count({col, row}) == 1)
            << "cell " << col << "," << row << " from the robot at " << robot.transpose();
      }
    EXPECT_EQ(free, drivable.connected_cells);
  }
}

TEST(SurfaceGridRules, TheRampsEndUnderTheDeckIsASeamBothDriveOver) {
  const MlsMap map = test::bridge_scene();
  const TraversabilityConfig traversability;
  // The deck and the ramp's upper part only (x in [-1.5, 1.5], y in [0, 10]): the road under the deck
  // is joined to them only outside. From the deck, over the seam at y = 5, down the ramp.
  const CellRegion deck_and_ramp{map.cell_of(-1.5, 0.0), 30, 100};
  const DrivableMap drivable = compute_drivable_map(map, traversability, {0.05, 2.05, 1.5}, deck_and_ramp);
  ASSERT_TRUE(drivable.start_found);
  EXPECT_NEAR(drivable.grid.surface_height_at(0.05, 5.05), 1.5, 0.05) << "the seam";
  EXPECT_EQ(drivable.grid.at_position(0.05, 8.05), Occupancy::free) << "the ramp";
  EXPECT_NEAR(drivable.grid.surface_height_at(0.05, 8.05), 1.2, 0.05);

  PatchGraphConfig graph_config;
  graph_config.traversability.unseen_gaps.max_gap = 0.0;
  const PatchGraph graph(std::make_shared<const SurfaceGrid>(map, deck_and_ramp, traversability),
                         map.resolution(), graph_config);
  const auto seam = graph.locate(0.05, 5.05, 1.5, 0.1);
  ASSERT_TRUE(seam.has_value());
  EXPECT_TRUE(graph.traversable(*seam));
}

TEST(SurfaceGridRules, TheRobotStandsOnAnyHorizontalPatchThePlannerOnlyOnTraversableOnes) {
  const MlsMap map = test::wall_and_stairs_scene();
  const SurfaceGrid surfaces(map, CellRegion::of_tiles(map.tile_indices()), TraversabilityConfig{});
  const auto [col, row] = surfaces.local(map.cell_of(0.05, 0.05));
  const auto standing = surfaces.nearest_surface(col, row, 0.0, 0.5, 0, SurfaceGrid::Standing::kHorizontal);
  const auto driving = surfaces.nearest_surface(col, row, 0.0, 0.5, 0, SurfaceGrid::Standing::kTraversable);
  ASSERT_TRUE(standing && driving);
  EXPECT_EQ(*standing, *driving) << "open floor is both";
  // In the wall's cell there is nothing to stand on; one ring out there is floor.
  const auto [wall_col, wall_row] = surfaces.local(map.cell_of(-2.95, 0.05));
  const auto in_wall =
      surfaces.nearest_surface(wall_col, wall_row, 0.0, 0.5, 0, SurfaceGrid::Standing::kHorizontal);
  EXPECT_FALSE(in_wall.has_value());
  const auto beside_wall =
      surfaces.nearest_surface(wall_col, wall_row, 0.0, 0.5, 1, SurfaceGrid::Standing::kHorizontal);
  ASSERT_TRUE(beside_wall.has_value());
  EXPECT_FALSE(surfaces.surface(*beside_wall).vertical);
  EXPECT_NE(surfaces.cell_of_surface(*beside_wall), surfaces.cell(wall_col, wall_row));
  EXPECT_FALSE(surfaces.nearest_surface(col, row, std::nan(""), 0.5, 3, SurfaceGrid::Standing::kHorizontal));
}

// Issue 58: on the campus bridge, the deck's underside, seen from the road, and its top made one vertical
// patch in most of the deck's cells, and no goal on the deck could be reached. A slab's top is ground
// where ground continues it on every side; the railings along it and the deck's edge are not.
TEST(SurfaceGridRules, ADeckSeenFromBelowAndAboveIsDrivenOnItsRailingsAreNot) {
  MlsMap map(test::scene_config());
  PointCloud road, top, underside, railings;
  test::add_plane(road, -6, 6, -4, 4, 0.0, 0.05);
  test::add_surface(
      top, -4, 4, -1.25, 1.25, [](double, double) { return 1.5; }, 0.05, 0.02);
  // Seen from below in blobs, as a lidar on the road sees it between the pillars: squares of 0.5 m.
  test::add_surface(
      underside, -4, 4, -1.25, 1.25, [](double, double) { return 1.2; }, 0.05, 0.0);
  std::erase_if(underside, [](const Eigen::Vector3d& p) {
    return (static_cast<int>(std::floor(p.x() / 0.5)) + static_cast<int>(std::floor(p.y() / 0.5))) % 2 != 0;
  });
  test::add_vertical_face(railings, -4, -1.32, 4, -1.32, 1.5, 2.5, 0.05);
  test::add_vertical_face(railings, -4, 1.32, 4, 1.32, 1.5, 2.5, 0.05);
  map.insert_scan(road, {0, 0, 0.5});
  map.insert_scan(underside, {0, 0, 0.5});
  map.insert_scan(top, {0, 0, 2.5});
  map.insert_scan(railings, {0, 0, 2.5});

  const SurfaceGrid grid(map, CellRegion::of_tiles(map.tile_indices()), TraversabilityConfig{});
  std::size_t slabs = 0, slabs_traversable = 0, railing = 0, railing_traversable = 0;
  for (std::size_t c = 0; c + 1 < grid.region().width * static_cast<std::size_t>(grid.region().height); ++c)
    for (const SurfaceGrid::Surface& s : grid.surfaces(c)) {
      if (s.vertical && s.top > 1.4F && s.top < 1.6F && s.bottom < 1.3F) {
        ++slabs;
        slabs_traversable += s.traversable ? 1 : 0;
      }
      if (s.top > 2.4F) {
        ++railing;
        railing_traversable += s.traversable ? 1 : 0;
      }
    }
  ASSERT_GT(slabs, 1000U) << "half the deck's cells are slabs";
  EXPECT_GT(static_cast<double>(slabs_traversable), 0.85 * static_cast<double>(slabs)) << "all but the edges";
  ASSERT_GT(railing, 100U);
  EXPECT_EQ(railing_traversable, 0U) << "a railing's top is not ground";

  PatchGraphConfig graph_config;
  const PatchGraph graph(std::make_shared<const SurfaceGrid>(grid), map.resolution(), graph_config);
  const PatchPath across = plan_on_patches(graph, {-3.0, 0.05, 1.5}, {.x = 3.0, .y = 0.05, .z = 1.5});
  EXPECT_TRUE(across.found()) << describe(across.status);
  EXPECT_NEAR(across.length, 6.0, 0.5);
  // The deck's edges have ground at its height on one side only: its top there is not ground, and it
  // holds no robot (the deck is 2.5 m wide, the robot 0.9 m).
  const auto edge = graph.locate(0.05, 1.25, 1.5, 0.1);
  EXPECT_TRUE(!edge || !graph.passable(*edge));
  // Under the deck, the road: clear for the robot, 1.2 m below the underside.
  const PatchPath under = plan_on_patches(graph, {-5.5, 0.05, 0.0}, {.x = 5.5, .y = 0.05, .z = 0.0});
  EXPECT_TRUE(under.found()) << describe(under.status);
}

/// Of the horizontal surfaces the map holds over a box (x, y within it, top within [z0, z1]), the share
/// the classification calls traversable: what the colour view paints green.
double traversable_share(const SurfaceGrid& grid, double resolution, Eigen::AlignedBox3d box,
                         std::size_t& seen) {
  const CellRegion& region = grid.region();
  std::size_t traversable = 0;
  seen = 0;
  for (int row = 0; row < region.height; ++row)
    for (int col = 0; col < region.width; ++col) {
      const Eigen::Vector3d centre((region.min.x + col + 0.5) * resolution,
                                   (region.min.y + row + 0.5) * resolution, box.center().z());
      if (!box.contains(centre))
        continue;
      for (const SurfaceGrid::Surface& s : grid.surfaces(grid.cell(col, row)))
        if (!s.vertical && static_cast<double>(s.top) >= box.min().z() &&
            static_cast<double>(s.top) <= box.max().z()) {
          ++seen;
          traversable += s.traversable ? 1 : 0;
          break;
        }
    }
  return seen == 0 ? 0.0 : static_cast<double>(traversable) / static_cast<double>(seen);
}

// A lidar sees a ramp from afar in rings: some cells empty, the rest scattered a few centimetres by its
// pose's tilt error. The slope rule reads the ramp, not the scatter; a slope too steep stays too steep.
TEST(SurfaceGridRules, ASlopeSeenInSparseScatteredRingsIsJudgedByItsGrade) {
  const auto share_of = [](double grade) {
    MlsMap map;
    std::mt19937 random(7);
    std::normal_distribution<double> scatter(0.0, 0.03);
    std::bernoulli_distribution seen(0.6);
    PointCloud points;
    for (double x = 0.05; x < 4.0; x += 0.1)
      for (double y = 0.05; y < 2.0; y += 0.1)
        if (seen(random))
          points.emplace_back(x, y, grade * x + scatter(random));
    map.insert_scan(points, {2.0, 1.0, 3.0});
    const SurfaceGrid grid(map, CellRegion::of_tiles(map.tile_indices()), TraversabilityConfig{});
    std::size_t cells = 0;
    const double share = traversable_share(
        grid, map.resolution(), {Eigen::Vector3d(0.3, 0.3, -1.0), Eigen::Vector3d(3.7, 1.7, 3.0)}, cells);
    EXPECT_GT(cells, 150U);
    return share;
  };
  EXPECT_GE(share_of(1.0 / 12.0), 0.95) << "a 1:12 ramp, 4.8 degrees";
  EXPECT_GE(share_of(0.0), 0.95) << "flat ground";
  EXPECT_LE(share_of(0.47), 0.05) << "25 degrees";
}

TEST(SurfaceGridRules, TheLabFloorAndTheRampTheRobotDroveAreTraversable) {
  // Issue 21: the colour view painted the flat lab floor and the 5.7 degree entrance ramp mostly amber
  // ("too steep or low ceiling"). The demo's robot (tilting scanner) drives from the lab down the hallway
  // and the ramp; its scans are mapped at the simulator's true poses, with the ground it drove.
  auto world = std::make_shared<const sim::World>(sim::builtin_world("campus"));
  sim::Simulator simulator(world, sim::SimulatorConfig{});
  MlsMap map{MlsConfig{}};
  for (double t = 0.0; t < 270.0; t += 0.1) {
    simulator.step(0.1);
    for (const ScanEvent& scan : simulator.take_scans())
      test::map_at_truth(map, scan);
  }
  ASSERT_GT(simulator.sample().truth->position.x(), 55.0) << "down the ramp by now";
  const SurfaceGrid grid(map, CellRegion::of_tiles(map.tile_indices()), TraversabilityConfig{});
  std::size_t seen = 0;
  // The lab's floor (0.45 m up) 0.3 m clear of its walls; the ramp between its side edges.
  const double lab = traversable_share(
      grid, map.resolution(), {Eigen::Vector3d(0.5, 7.0, 0.40), Eigen::Vector3d(13.7, 11.5, 0.50)}, seen);
  EXPECT_GT(seen, 4000U);
  EXPECT_GE(lab, 0.95);
  const double ramp = traversable_share(
      grid, map.resolution(), {Eigen::Vector3d(49.6, 4.35, -0.05), Eigen::Vector3d(54.8, 6.15, 0.50)}, seen);
  EXPECT_GT(seen, 700U);
  EXPECT_GE(ramp, 0.95);
}

/// Ground from x = 0 to 8 m, y = -2 to 2 m, at z = 0 for x < 4 and `curb` beyond, a point every `step`,
/// seen from `origin`, in stripes 0.5 m wide across x that lie `offset` above and below it in turn: from
/// afar (sigma 0.14-0.18 m, MlsConfig) each stripe is a ring of one far revolution, whose tilt error
/// times the range lifts or sinks it, as the campus lidar's live map at 5x holds its ground (issue 58).
MlsMap ground_with_curb(double curb, const Eigen::Vector3d& origin, double step, double offset) {
  MlsMap map;
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0.0, 0.002);
  PointCloud points;
  for (double x = step / 2; x < 8.0; x += step)
    for (double y = -2.0 + step / 2; y < 2.0; y += step) {
      const double stripe = static_cast<int>(std::floor(x / 0.5)) % 2 == 0 ? offset : -offset;
      points.emplace_back(x, y, (x < 4.0 ? 0.0 : curb) + stripe + noise(random));
    }
  map.insert_scan(points, origin);
  return map;
}

PatchPath plan_across(const MlsMap& map, double curb, const TraversabilityConfig& traversability) {
  PatchGraphConfig graph_config;
  graph_config.traversability = traversability;
  const PatchGraph graph(
      std::make_shared<const SurfaceGrid>(map, CellRegion::of_tiles(map.tile_indices()), traversability),
      map.resolution(), graph_config);
  return plan_on_patches(graph, {1.0, 0.0, 0.0}, {.x = 7.0, .y = 0.0, .z = curb});
}

// Issue 58: at 5x the campus lidar's live map held the plateau as cells seen once from 20-30 m, 0.08-0.1 m
// from their neighbours: steps to a rule that took heights as exact, and every one an edge the robot's
// 0.45 m had to keep clear of, so flat ground had no room and the robot was stranded. A height difference
// the patches' own uncertainty explains is no step; a curb seen well is one, and so is a high one seen
// from afar.
TEST(SurfaceGridRules, ThinFlatGroundSeenFromAfarIsDrivableACurbSeenWellIsNot) {
  const Eigen::Vector3d far(-25.0, 0.0, 2.0);
  const TraversabilityConfig rules;
  TraversabilityConfig exact = rules;  // heights taken as exact: the rule before
  exact.step_sigmas = 0.0;

  const MlsMap thin = ground_with_curb(0.0, far, 0.1, 0.043);  // stripes 0.086 m apart
  const PatchPath across = plan_across(thin, 0.0, rules);
  EXPECT_TRUE(across.found()) << describe(across.status);
  EXPECT_NEAR(across.length, 6.0, 1.0);
  EXPECT_FALSE(plan_across(thin, 0.0, exact).found()) << "heights taken as exact leave no room";

  // A 0.1 m curb seen from 2-4 m by many points: known to a centimetre, a step.
  const MlsMap curb_seen_well = ground_with_curb(0.1, {4.0, 0.0, 1.5}, 0.04, 0.0);
  EXPECT_EQ(plan_across(curb_seen_well, 0.1, rules).status, PatchPlanStatus::no_path)
      << describe(plan_across(curb_seen_well, 0.1, rules).status);
  // Beyond what uncertainty may forgive (max_step + max_uncertain_step), a curb seen from afar is one too.
  const MlsMap high_curb_from_afar = ground_with_curb(0.3, far, 0.1, 0.043);
  EXPECT_FALSE(plan_across(high_curb_from_afar, 0.3, rules).found());
  // The same ground seen well, flat: drivable under both rules.
  const MlsMap flat_seen_well = ground_with_curb(0.0, {4.0, 0.0, 1.5}, 0.04, 0.0);
  EXPECT_TRUE(plan_across(flat_seen_well, 0.0, rules).found());
  EXPECT_TRUE(plan_across(flat_seen_well, 0.0, exact).found());
}

/// A ramp up x (grade 0.1, x = 0 to 8 m, y = -2 to 2 m), a point every 0.1 m, seen from `near`, but for a
/// ring across it at x = 4.0-4.3 m, `depth` below it, seen from `ring_origin` alone.
MlsMap ramp_with_low_ring(const Eigen::Vector3d& near, const Eigen::Vector3d& ring_origin, double depth) {
  MlsMap map;
  PointCloud ramp;
  PointCloud ring;
  for (double x = 0.05; x < 8.0; x += 0.1)
    for (double y = -1.95; y < 2.0; y += 0.1) {
      if (x > 4.0 && x < 4.3)
        ring.emplace_back(x, y, 0.1 * x - depth);
      else
        ramp.emplace_back(x, y, 0.1 * x);
    }
  map.insert_scan(ramp, near);
  map.insert_scan(ring, ring_origin);
  return map;
}

// Issue 58: the lidar demo's ramp seen from the bridge deck 12 m away held a ring across it in cells no
// near scan had reached, 0.12-0.25 m below the ramp (sigma 0.12-0.22 m); the slope rule fitted those
// cells a plane of their own, too steep, and every goal down the ramp was refused. Weighed by how sure
// each height is, the ramp's certain cells decide, and the ring's step is within what its uncertainty
// explains; the same ring seen well is a trench, and a trench seen from afar deeper than the uncertainty
// forgives is one too.
TEST(SurfaceGridRules, AFarLowRingAcrossARampDoesNotCloseItARingSeenWellDoes) {
  const TraversabilityConfig rules;
  const Eigen::Vector3d near(4.0, 0.0, 1.5);
  const Eigen::Vector3d far(30.0, 0.0, 5.0);
  const auto plan_up = [&](const MlsMap& map) {
    PatchGraphConfig graph_config;
    graph_config.traversability = rules;
    const PatchGraph graph(
        std::make_shared<const SurfaceGrid>(map, CellRegion::of_tiles(map.tile_indices()), rules),
        map.resolution(), graph_config);
    return plan_on_patches(graph, {1.0, 0.0, 0.1}, {.x = 7.0, .y = 0.0, .z = 0.7});
  };
  const PatchPath across = plan_up(ramp_with_low_ring(near, far, 0.15));
  EXPECT_TRUE(across.found()) << describe(across.status);
  EXPECT_NEAR(across.length, 6.0, 1.0);
  EXPECT_FALSE(plan_up(ramp_with_low_ring(near, near, 0.15)).found()) << "a trench seen well";
  EXPECT_FALSE(plan_up(ramp_with_low_ring(near, far, 0.4)).found()) << "deeper than uncertainty forgives";
}

}  // namespace
}  // namespace strata

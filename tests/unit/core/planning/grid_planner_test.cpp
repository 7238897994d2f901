// The grid planner on hand-made grids: lengths, the no-corner-cutting rule, unreachable goals, inflation,
// and A* against the wavefront on random grids.
#include "core/planning/grid_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/planning/astar.hpp"
#include "core/planning/obstacle_inflation.hpp"
#include "core/planning/wavefront.hpp"

namespace strata {
namespace {

constexpr double kSqrt2 = 1.4142135623730951;

/// A grid from text rows ('.' free, '#' occupied, '?' unknown); row i is y = i.
OccupancyGrid grid_from(const std::vector<std::string>& rows, double resolution = 1.0) {
  OccupancyGrid grid(static_cast<int>(rows[0].size()), static_cast<int>(rows.size()), resolution);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const char c = rows[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)];
      grid.at({x, y}) = c == '#' ? CellState::occupied : c == '?' ? CellState::unknown : CellState::free;
    }
  return grid;
}

/// Checks a path step by step: adjacent cells, all passable, diagonals only past two free cells.
void expect_valid_path(const TraversableGrid& grid, const std::vector<GridCell>& cells) {
  for (std::size_t i = 0; i < cells.size(); ++i) {
    EXPECT_TRUE(grid.passable(cells[i])) << "cell " << i << " blocked";
    if (i == 0)
      continue;
    const int dx = cells[i].x - cells[i - 1].x;
    const int dy = cells[i].y - cells[i - 1].y;
    ASSERT_TRUE(std::abs(dx) <= 1 && std::abs(dy) <= 1 && (dx != 0 || dy != 0))
        << "step " << i << " not a move";
    if (dx != 0 && dy != 0) {
      EXPECT_TRUE(grid.passable({cells[i - 1].x + dx, cells[i - 1].y})) << "corner cut at step " << i;
      EXPECT_TRUE(grid.passable({cells[i - 1].x, cells[i - 1].y + dy})) << "corner cut at step " << i;
    }
  }
}

TEST(GridPlanner, StraightLength) {
  GridPlanner planner(grid_from({"..........", ".........."}));
  const GridPath path = planner.plan({0, 0}, {9, 0});
  ASSERT_TRUE(path.found());
  EXPECT_DOUBLE_EQ(path.length, 9.0);
  EXPECT_EQ(path.cells.size(), 10U);
  EXPECT_EQ(path.cells.front(), (GridCell{0, 0}));
  EXPECT_EQ(path.cells.back(), (GridCell{9, 0}));
}

TEST(GridPlanner, DiagonalLengths) {
  GridPlanner planner(grid_from(std::vector<std::string>(5, ".....")));
  for (const SearchMethod method : {SearchMethod::jump_point, SearchMethod::astar}) {
    EXPECT_NEAR(planner.plan({0, 0}, {4, 4}, method).length, 4 * kSqrt2, 1e-12);
    EXPECT_NEAR(planner.plan({0, 0}, {4, 2}, method).length, 2 + 2 * kSqrt2, 1e-12);
    EXPECT_NEAR(planner.plan({4, 0}, {0, 3}, method).length, 1 + 3 * kSqrt2, 1e-12);
    EXPECT_EQ(planner.plan({4, 0}, {0, 3}, method).cells.size(), 5U);
  }
}

TEST(GridPlanner, NoCornerCuttingThroughADiagonalGap) {
  // The two free cells touch only at a corner: no path at all.
  GridPlanner gap(grid_from({".#", "#."}));
  const GridPath through = gap.plan({0, 0}, {1, 1});
  EXPECT_FALSE(through.found());
  EXPECT_EQ(through.status, PlanStatus::no_path);
  // One corner blocked: the diagonal is not allowed, the path goes round (2, not sqrt 2).
  GridPlanner corner(grid_from({"..", "#."}));
  const GridPath around = corner.plan({0, 0}, {1, 1});
  ASSERT_TRUE(around.found());
  EXPECT_DOUBLE_EQ(around.length, 2.0);
  expect_valid_path(corner.traversable(), around.cells);
}

TEST(GridPlanner, UnreachableGoalIsReportedWithoutSearching) {
  GridPlanner planner(grid_from({
      "....#....",
      "....#....",
      "....#....",
      "....#....",
  }));
  const GridPath path = planner.plan({0, 0}, {8, 3});
  EXPECT_EQ(path.status, PlanStatus::no_path);
  EXPECT_TRUE(path.cells.empty());
  EXPECT_EQ(path.expanded, 0U);  // the region labels answer it
  EXPECT_EQ(planner.plan({4, 1}, {0, 0}).status, PlanStatus::start_blocked);
  EXPECT_EQ(planner.plan({0, 0}, {4, 2}).status, PlanStatus::goal_blocked);
  EXPECT_EQ(planner.plan({-1, 0}, {0, 0}).status, PlanStatus::start_outside);
  EXPECT_EQ(planner.plan({0, 0}, {9, 0}).status, PlanStatus::goal_outside);
  const CostField field = planner.wavefront({8, 3});
  EXPECT_EQ(planner.follow(field, {0, 0}).status, PlanStatus::no_path);
}

TEST(GridPlanner, StartEqualsGoal) {
  GridPlanner planner(grid_from({"...", "..."}));
  const GridPath path = planner.plan({1, 1}, {1, 1});
  ASSERT_TRUE(path.found());
  EXPECT_EQ(path.length, 0.0);
  ASSERT_EQ(path.cells.size(), 1U);
  EXPECT_EQ(path.cells[0], (GridCell{1, 1}));
  const GridPath followed = planner.follow(planner.wavefront({1, 1}), {1, 1});
  ASSERT_TRUE(followed.found());
  EXPECT_EQ(followed.length, 0.0);
}

TEST(GridPlanner, InflationClosesANarrowGap) {
  // A wall with a 3-cell gap (0.3 m at 0.1 m per cell).
  std::vector<std::string> rows(15, "...............");
  rows[7] = "######...######";
  const OccupancyGrid grid = grid_from(rows, 0.1);
  const GridPath thin = GridPlanner(grid, {0.1, true}).plan({7, 0}, {7, 14});
  ASSERT_TRUE(thin.found());  // the centre cell of the gap is 0.2 m from the wall
  EXPECT_DOUBLE_EQ(thin.length, 14.0);
  const GridPath wide = GridPlanner(grid, {0.2, true}).plan({7, 0}, {7, 14});
  EXPECT_EQ(wide.status, PlanStatus::no_path);
}

TEST(ObstacleInflation, BlocksCellsWithinTheRadiusOfCentres) {
  OccupancyGrid grid(9, 9);
  grid.at({4, 4}) = CellState::occupied;
  const std::vector<std::uint8_t> blocked = inflate_obstacles(grid, 2.0);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 9; ++x) {
      const double distance = std::hypot(x - 4, y - 4);
      EXPECT_EQ(blocked[grid.index({x, y})] != 0, distance <= 2.0) << x << "," << y;
    }
  EXPECT_EQ(inflate_obstacles(grid, 0.0), inflate_obstacles(grid, 0.99));  // under one cell: obstacles only
}

TEST(ObstacleInflation, MatchesBruteForceOnARandomGrid) {
  std::mt19937 random(7);
  OccupancyGrid grid(41, 33, 0.05);
  std::vector<GridCell> obstacles;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
      if (random() % 40 == 0) {
        grid.at({x, y}) = CellState::occupied;
        obstacles.push_back({x, y});
      }
  for (const double radius_m : {0.05, 0.12, 0.2, 0.37}) {
    const std::vector<std::uint8_t> blocked = inflate_obstacles(grid, radius_m);
    const double radius = radius_m / grid.resolution;
    for (int y = 0; y < grid.height; ++y)
      for (int x = 0; x < grid.width; ++x) {
        bool near = false;
        for (const GridCell& o : obstacles)
          near = near || std::hypot(o.x - x, o.y - y) <= radius + 1e-9;
        ASSERT_EQ(blocked[grid.index({x, y})] != 0, near) << x << "," << y << " radius " << radius_m;
      }
  }
}

TEST(GridPlanner, UnknownCellsAreBlockedUnlessConfigured) {
  const OccupancyGrid grid = grid_from({"..?..", "##?##"});
  EXPECT_EQ(GridPlanner(grid).plan({0, 0}, {4, 0}).status, PlanStatus::no_path);
  const GridPath through = GridPlanner(grid, {0.0, false}).plan({0, 0}, {4, 0});
  ASSERT_TRUE(through.found());
  EXPECT_DOUBLE_EQ(through.length, 4.0);
}

TEST(GridPlanner, JumpPointSearchAStarAndWavefrontAgreeOnRandomGrids) {
  std::mt19937 random(42);
  for (int trial = 0; trial < 20; ++trial) {
    OccupancyGrid grid(30 + trial, 25);
    for (CellState& cell : grid.cells)
      cell = static_cast<int>(random() % 100) < 5 + 2 * trial ? CellState::occupied : CellState::free;
    GridPlanner planner(grid);
    const TraversableGrid& traversable = planner.traversable();
    std::uniform_int_distribution<int> x_of(0, grid.width - 1);
    std::uniform_int_distribution<int> y_of(0, grid.height - 1);
    const GridCell goal{x_of(random), y_of(random)};
    const CostField field = planner.wavefront(goal);
    for (int q = 0; q < 20; ++q) {
      const GridCell start{x_of(random), y_of(random)};
      const GridPath j = planner.plan(start, goal);
      const GridPath a = planner.plan(start, goal, SearchMethod::astar);
      const GridPath w = planner.follow(field, start);
      ASSERT_EQ(a.status, w.status);
      ASSERT_EQ(j.status, w.status);
      if (!a.found())
        continue;
      EXPECT_NEAR(a.length, w.length, 1e-9);
      EXPECT_NEAR(j.length, w.length, 1e-9);
      EXPECT_EQ(j.cells.front(), start);
      EXPECT_EQ(j.cells.back(), goal);
      expect_valid_path(traversable, j.cells);
      EXPECT_NEAR(w.length, field.at(traversable, start), 1e-9);
      EXPECT_GE(a.length, octile_distance(start, goal) - 1e-9);
      EXPECT_EQ(a.cells.front(), start);
      EXPECT_EQ(a.cells.back(), goal);
      EXPECT_EQ(w.cells.front(), start);
      EXPECT_EQ(w.cells.back(), goal);
      expect_valid_path(traversable, a.cells);
      expect_valid_path(traversable, w.cells);
    }
  }
}

}  // namespace
}  // namespace strata

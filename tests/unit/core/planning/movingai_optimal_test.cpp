// Every query of the MovingAI scenario files in STRATA_DATA_DIR against its published optimal length
// (grid cell size 1, robot radius 0). Skipped with a message when the data is absent.
//
// All six sets use the movement rule the planner implements (8-connected, diagonal sqrt 2, diagonal moves
// only past two free orthogonal cells), as the data README verified. A length of 0 with start != goal marks
// a goal with no path (two rmtst01 queries): the planner must report it unreachable.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <string>

#include "core/planning/grid_planner.hpp"
#include "drivers/io/movingai_reader.hpp"

namespace strata {
namespace {

namespace fs = std::filesystem;

fs::path data_dir() {
  const char* from_env = std::getenv("STRATA_DATA_DIR");
  return from_env != nullptr ? fs::path(from_env) : fs::path(STRATA_DATA_DIR);
}

struct ScenarioSet {
  const char* map;
  const char* scenario;
  std::size_t queries;  ///< rows in the file, per the data README
  int astar_every;      ///< also check plain A* on every n-th query (jump point search checks them all)
  int wavefront_every;  ///< and the wavefront (it floods the whole map)
};

void PrintTo(const ScenarioSet& set, std::ostream* out) {
  *out << set.scenario;
}  // readable test names

class MovingAiOptimal : public ::testing::TestWithParam<ScenarioSet> {};

TEST_P(MovingAiOptimal, EveryQueryMatchesThePublishedLength) {
  const ScenarioSet& set = GetParam();
  const fs::path map_path = data_dir() / "movingai" / set.map;
  const fs::path scenario_path = data_dir() / "movingai" / set.scenario;
  if (!fs::exists(map_path) || !fs::exists(scenario_path))
    GTEST_SKIP() << "MovingAI data not found at " << map_path << " (set STRATA_DATA_DIR)";
  const OccupancyGrid grid = io::read_movingai_map(map_path);
  const io::MovingAiScenario scenario = io::read_movingai_scenario(scenario_path);
  ASSERT_EQ(scenario.queries.size(), set.queries);
  GridPlanner planner(grid);

  std::size_t matched = 0;
  std::size_t unreachable = 0;
  for (std::size_t i = 0; i < scenario.queries.size(); ++i) {
    const io::MovingAiQuery& query = scenario.queries[i];
    ASSERT_EQ(query.map_width, grid.width);
    ASSERT_EQ(query.map_height, grid.height);
    const bool no_path = query.optimal_length == 0.0 && !(query.start == query.goal);
    const GridPath path = planner.plan(query.start, query.goal);
    GridPath astar;
    const bool check_astar = i % static_cast<std::size_t>(set.astar_every) == 0;
    if (check_astar)
      astar = planner.plan(query.start, query.goal, SearchMethod::astar);
    GridPath followed;
    const bool check_wavefront = i % static_cast<std::size_t>(set.wavefront_every) == 0;
    if (check_wavefront)
      followed = planner.follow(planner.wavefront(query.goal), query.start);
    const std::string where = std::string(set.scenario) + " row " + std::to_string(i + 2);
    if (no_path) {
      EXPECT_FALSE(path.found()) << where << ": listed as no path, planner found " << path.length;
      if (check_wavefront) {
        EXPECT_FALSE(followed.found()) << where;
      }
      if (check_astar) {
        EXPECT_FALSE(astar.found()) << where;
      }
      unreachable += path.found() ? 0 : 1;
      continue;
    }
    ASSERT_TRUE(path.found()) << where << ": " << describe(path.status);
    EXPECT_NEAR(path.length, query.optimal_length, 1e-3) << where;
    if (check_astar) {
      ASSERT_TRUE(astar.found()) << where;
      EXPECT_NEAR(astar.length, query.optimal_length, 1e-3) << where << " (A*)";
    }
    if (check_wavefront) {
      ASSERT_TRUE(followed.found()) << where;
      EXPECT_NEAR(followed.length, query.optimal_length, 1e-3) << where << " (wavefront)";
    }
    matched += std::abs(path.length - query.optimal_length) <= 1e-3 ? 1 : 0;
  }
  std::printf("[ MovingAI ] %s: %zu of %zu queries match the optimal length, %zu reported unreachable\n",
              set.scenario, matched, scenario.queries.size(), unreachable);
  EXPECT_EQ(matched + unreachable, scenario.queries.size());
}

INSTANTIATE_TEST_SUITE_P(
    Scenarios, MovingAiOptimal,
    ::testing::Values(
        ScenarioSet{"pathfindingjs/64room_000.map", "pathfindingjs/64room_000.map.scen", 2030, 50, 200},
        ScenarioSet{"pathfindingjs/arena.map", "pathfindingjs/arena.map.scen", 160, 1, 1},
        ScenarioSet{"anonsar_dao_arena/arena.map", "anonsar_dao_arena/arena.map.scen", 130, 1, 1},
        ScenarioSet{"gppc/rmtst01.map", "gppc/rmtst01.map.scen", 470, 1, 1},
        ScenarioSet{"mapf/random-32-32-10.map", "mapf/random-32-32-10-random-1.scen", 461, 1, 1},
        ScenarioSet{"mapf/random-32-32-20.map", "mapf/random-32-32-20-random-1.scen", 409, 1, 1}),
    [](const ::testing::TestParamInfo<ScenarioSet>& param_info) {
      std::string name = param_info.param.scenario;
      for (char& c : name)
        if (std::isalnum(static_cast<unsigned char>(c)) == 0)
          c = '_';
      return name;
    });

}  // namespace
}  // namespace strata

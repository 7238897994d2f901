// `strata plan` as a script runs it: the real binary on Nav2's benchmark map (skipped without the data) and
// on small maps written here.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kNoPath = 3;  // documented in `strata plan --help` and the README

/// A small MovingAI map with a wall splitting it into two halves, removed at the end.
class WalledMap {
 public:
  WalledMap() {
    std::ofstream(path_) << "type octile\nheight 3\nwidth 5\nmap\n"
                            "..@..\n"
                            "..@..\n"
                            "..@..\n";
  }
  ~WalledMap() { fs::remove(path_); }
  [[nodiscard]] std::string path() const { return path_.string(); }

 private:
  fs::path path_ = private_temp_path("strata_plan_walled", ".map");
};

TEST(PlanCommand, PlansCornerToCornerOnTheNav2Map) {
  const fs::path yaml = data_dir() / "nav2/100by100_20.yaml";
  if (!fs::exists(yaml))
    GTEST_SKIP() << "Nav2 map not found at " << yaml << " (set STRATA_DATA_DIR)";
  const CommandResult run = run_strata({"plan", "--map", yaml.string(), "--start", "1,1", "--goal", "99,99",
                                        "--robot-radius", "0.22", "--json", "--path"},
                                       std::chrono::seconds(120));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json out = json_of(run);
  ASSERT_TRUE(out.is_object()) << run.output;
  EXPECT_EQ(out["found"], true);
  EXPECT_EQ(out["units"], "m");
  EXPECT_EQ(out["method"], "jps");
  const double length = out["length"].get<double>();
  EXPECT_GE(length, 98.0 * std::sqrt(2.0) - 0.1);  // at least the straight line between the cell centres
  EXPECT_LT(length, 98.0 * std::sqrt(2.0) * 1.3);
  EXPECT_GT(out["expanded"].get<int>(), 0);
  EXPECT_GT(out["seconds"].get<double>(), 0.0);
  EXPECT_GE(out["preparation_seconds"].get<double>(), 0.0);
  EXPECT_EQ(out["map"]["width"], 2000);
  EXPECT_DOUBLE_EQ(out["map"]["resolution"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(out["robot_radius"].get<double>(), 0.22);
  const nlohmann::json& path = out["path"];
  ASSERT_GT(path.size(), 1000U);
  EXPECT_NEAR(path.front()[0].get<double>(), 1.025, 1e-9);  // the start cell's centre
  EXPECT_NEAR(path.front()[1].get<double>(), 1.025, 1e-9);
  EXPECT_NEAR(path.back()[0].get<double>(), 99.025, 1e-9);
  EXPECT_NEAR(path.back()[1].get<double>(), 99.025, 1e-9);
  double summed = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i)
    summed += std::hypot(path[i][0].get<double>() - path[i - 1][0].get<double>(),
                         path[i][1].get<double>() - path[i - 1][1].get<double>());
  EXPECT_NEAR(summed, length, 1e-6);

  // The same query with A* and with the wavefront: the same optimal length.
  const CommandResult astar = run_strata({"plan", "--map", yaml.string(), "--start", "1,1", "--goal", "99,99",
                                          "--robot-radius", "0.22", "--json", "--method", "astar"},
                                         std::chrono::seconds(120));
  ASSERT_EQ(astar.exit_code, 0) << astar.output;
  EXPECT_NEAR(json_of(astar)["length"].get<double>(), length, 1e-6);
  EXPECT_GT(json_of(astar)["expanded"].get<int>(), out["expanded"].get<int>());
  const CommandResult wavefront =
      run_strata({"plan", "--map", yaml.string(), "--start", "1,1", "--goal", "99,99", "--robot-radius",
                  "0.22", "--json", "--method", "wavefront"},
                 std::chrono::seconds(120));
  ASSERT_EQ(wavefront.exit_code, 0) << wavefront.output;
  EXPECT_NEAR(json_of(wavefront)["length"].get<double>(), length, 1e-6);
}

TEST(PlanCommand, GoalInsideAnObstacleOfTheNav2MapExitsNonZero) {
  const fs::path yaml = data_dir() / "nav2/100by100_20.yaml";
  if (!fs::exists(yaml))
    GTEST_SKIP() << "Nav2 map not found at " << yaml << " (set STRATA_DATA_DIR)";
  // (54.5, 49.7) m is image column 1090, row 1005: inside an obstacle blob.
  const CommandResult run = run_strata(
      {"plan", "--map", yaml.string(), "--start", "1,1", "--goal", "54.5,49.7"}, std::chrono::seconds(120));
  EXPECT_EQ(run.exit_code, kNoPath) << run.output;
  EXPECT_NE(run.output.find("unreachable: the goal is blocked"), std::string::npos) << run.output;
}

TEST(PlanCommand, DisconnectedGoalExitsNonZeroWithAClearMessage) {
  const WalledMap map;
  const CommandResult run = run_strata({"plan", "--map", map.path(), "--start", "0,0", "--goal", "4,2"});
  EXPECT_EQ(run.exit_code, kNoPath) << run.output;
  EXPECT_NE(run.output.find("unreachable: no path"), std::string::npos) << run.output;
  const CommandResult json =
      run_strata({"plan", "--map", map.path(), "--start", "0,0", "--goal", "4,2", "--json"});
  EXPECT_EQ(json.exit_code, kNoPath) << json.output;
  const nlohmann::json out = json_of(json);
  EXPECT_EQ(out["found"], false);
  EXPECT_TRUE(out["length"].is_null());
}

TEST(PlanCommand, StartFarOutsideTheMapExitsNonZero) {
  const WalledMap map;
  const CommandResult run = run_strata({"plan", "--map", map.path(), "--start", "1e20,0", "--goal", "0,0"});
  EXPECT_EQ(run.exit_code, kNoPath) << run.output;
  EXPECT_NE(run.output.find("unreachable: the start is outside the map"), std::string::npos) << run.output;
}

TEST(PlanCommand, MovingAiMapInCells) {
  const WalledMap map;
  const CommandResult run = run_strata({"plan", "--map", map.path(), "--start", "0,0", "--goal", "1,2",
                                        "--json", "--path", "--method", "jps"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json out = json_of(run);
  EXPECT_EQ(out["units"], "cells");
  EXPECT_NEAR(out["length"].get<double>(), 1.0 + std::sqrt(2.0), 1e-9);
  ASSERT_EQ(out["path"].size(), 3U);
  EXPECT_EQ(out["path"][2], nlohmann::json::array({1.0, 2.0}));
}

TEST(PlanCommand, BadInputExitsWithOne) {
  const fs::path bad = private_temp_path("strata_plan_bad", ".yaml");
  { std::ofstream(bad) << "resolution: 0.05\n"; }
  const CommandResult run = run_strata({"plan", "--map", bad.string(), "--start", "0,0", "--goal", "1,1"});
  fs::remove(bad);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find(bad.filename().string()), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("missing image"), std::string::npos) << run.output;

  const WalledMap map;
  const CommandResult coordinates =
      run_strata({"plan", "--map", map.path(), "--start", "0", "--goal", "1,1"});
  EXPECT_EQ(coordinates.exit_code, 1);
  EXPECT_NE(coordinates.output.find("--start needs two numbers"), std::string::npos) << coordinates.output;
}

}  // namespace
}  // namespace strata::testing

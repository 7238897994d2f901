// `strata map build` and `strata map export` as a script runs them: the real binary on a scan it writes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

namespace fs = std::filesystem;

class MapCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("strata_map_command_" + std::to_string(::getpid()));
    fs::create_directories(directory_);
    // A 6 m x 4 m floor 0.5 m below the sensor with a 2 m wall at x = 2.55, as x y z lines.
    std::ofstream scan(directory_ / "scan.xyz");
    for (double x = -2.98; x < 3.0; x += 0.04)
      for (double y = -1.98; y < 2.0; y += 0.04)
        scan << x << ' ' << y << " -0.5\n";
    for (double y = -1.98; y < 2.0; y += 0.04)
      for (double z = 0.02; z < 2.0; z += 0.04)
        scan << "2.55 " << y << ' ' << z - 0.5 << '\n';
  }
  void TearDown() override { fs::remove_all(directory_); }
  fs::path directory_;
};

TEST_F(MapCommand, BuildsAMapThenExportsPlyAndRosMap) {
  const fs::path map = directory_ / "site.smls";
  const CommandResult build =
      run_strata({"map", "build", "--scans", (directory_ / "scan.xyz").string(), "-o", map.string()},
                 std::chrono::seconds(60));
  ASSERT_EQ(build.exit_code, 0) << build.output;
  const nlohmann::json built = json_of(build);
  ASSERT_TRUE(built.is_object()) << build.output;
  EXPECT_EQ(built["occupied_cells"].get<int>(), 60 * 40);
  ASSERT_TRUE(fs::exists(map));

  const CommandResult exported =
      run_strata({"map", "export", map.string(), "--ply", (directory_ / "site.ply").string(), "--pgm",
                  (directory_ / "site.yaml").string(), "--robot", "0,0,-0.5"},
                 std::chrono::seconds(60));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const nlohmann::json out = json_of(exported);
  ASSERT_TRUE(out.is_object()) << exported.output;
  // The wall is occupied; the floor on both sides of it free (59 x 40 cells), and the 55 x 40 in front of
  // it connected to the robot.
  EXPECT_EQ(out["free_cells"].get<int>(), 59 * 40);
  EXPECT_EQ(out["connected_cells"].get<int>(), 55 * 40);
  EXPECT_EQ(file_bytes(directory_ / "site.ply").rfind("ply\n", 0), 0U);
  EXPECT_EQ(file_bytes(directory_ / "site.pgm").rfind("P5\n", 0), 0U);
  EXPECT_NE(file_bytes(directory_ / "site.yaml").find("image: site.pgm"), std::string::npos);
}

TEST_F(MapCommand, TheRobotPointInTheOldFormWorksWithAWarning) {
  const fs::path map = directory_ / "site.smls";
  ASSERT_EQ(run_strata({"map", "build", "--scans", (directory_ / "scan.xyz").string(), "-o", map.string()},
                       std::chrono::seconds(60))
                .exit_code,
            0);
  const auto export_with = [&](const std::string& robot, const std::string& stem) {
    return run_strata(
        {"map", "export", map.string(), "--pgm", (directory_ / (stem + ".yaml")).string(), "--robot", robot},
        std::chrono::seconds(60));
  };
  const CommandResult current = export_with("0,0,-0.5", "current");
  ASSERT_EQ(current.exit_code, 0) << current.output;
  const CommandResult old = export_with("0 0 -0.5", "old");
  ASSERT_EQ(old.exit_code, 0) << old.output;
  EXPECT_NE(old.output.find("write --robot 0,0,-0.5"), std::string::npos) << old.output;
  EXPECT_EQ(file_bytes(directory_ / "old.pgm"), file_bytes(directory_ / "current.pgm"));

  const CommandResult wrong = export_with("0,0", "wrong");
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.output.find("--robot x,y,z"), std::string::npos) << wrong.output;
  EXPECT_FALSE(fs::exists(directory_ / "wrong.pgm"));
}

TEST_F(MapCommand, CorruptedMapFileFailsWithAClearMessage) {
  const fs::path map = directory_ / "site.smls";
  ASSERT_EQ(run_strata({"map", "build", "--scans", (directory_ / "scan.xyz").string(), "-o", map.string()},
                       std::chrono::seconds(60))
                .exit_code,
            0);
  std::string bytes = file_bytes(map);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x01);
  std::ofstream(map, std::ios::binary) << bytes;
  const CommandResult run = run_strata(
      {"map", "export", map.string(), "--ply", (directory_ / "x.ply").string()}, std::chrono::seconds(60));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("checksum"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(directory_ / "x.ply"));
}

}  // namespace
}  // namespace strata::testing

// `strata register` as a script runs it: the real binary on real scans (skipped without the data).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

namespace fs = std::filesystem;

TEST(RegisterCommand, RegistersTheRealRoomPairAndPrintsJson) {
  const fs::path dir = data_dir() / "pairs/pcl_room";
  if (!fs::exists(dir / "room_scan1.pcd"))
    GTEST_SKIP() << "real data not found at " << dir << " (set STRATA_DATA_DIR)";
  const CommandResult run =
      run_strata({"register", (dir / "room_scan2.pcd").string(), (dir / "room_scan1.pcd").string(), "--guess",
                  "1.79387 0.720047 0 0 0 0.6931", "--json"},
                 std::chrono::seconds(120));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json out = json_of(run);
  ASSERT_TRUE(out.is_object()) << run.output;
  EXPECT_EQ(out["verdict"], "accepted");
  EXPECT_EQ(out["reason"], "none");
  EXPECT_GT(out["pairs"].get<int>(), 500);
  EXPECT_GT(out["iterations"].get<int>(), 0);
  EXPECT_LT(out["rmse"].get<double>(), 0.15);
  EXPECT_GT(out["seconds"].get<double>(), 0.0);
  ASSERT_EQ(out["transform"].size(), 4U);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      m(r, c) = out["transform"][static_cast<std::size_t>(r)][static_cast<std::size_t>(c)].get<double>();
  EXPECT_TRUE(m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)));
  EXPECT_TRUE((m.topLeftCorner<3, 3>().transpose() * m.topLeftCorner<3, 3>()).isIdentity(1e-6));
  // Near the README's independent result: yaw 40.8 deg, t = (1.975, 0.059, 0.027) m.
  EXPECT_NEAR(m(0, 3), 1.975, 0.05);
  EXPECT_NEAR(m(1, 3), 0.059, 0.05);
  EXPECT_NEAR(out["pose"]["yaw"].get<double>(), 40.8 * 3.14159265358979 / 180.0, 0.01);
  EXPECT_EQ(out["source_points"]["read"].get<int>() + out["source_points"]["dropped"].get<int>(), 112624);
}

TEST(RegisterCommand, BadFileFailsWithAClearMessage) {
  const fs::path bad = private_temp_path("strata_register_bad", ".pcd");
  { std::ofstream(bad) << "not a point cloud\n"; }
  const CommandResult run = run_strata({"register", bad.string(), bad.string()});
  fs::remove(bad);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find(bad.filename().string()), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("not a PCD"), std::string::npos) << run.output;
}

TEST(RegisterCommand, TheGuessInDegreesWithCommasAndTheOldFormAgree) {
  // One pose syntax on the command line (as --lidar-mount): x,y,z,roll,pitch,yaw in metres and degrees. The
  // old form (spaces, radians) still works and says what to write instead.
  const fs::path dir = data_dir() / "pairs/pcl_room";
  if (!fs::exists(dir / "room_scan1.pcd"))
    GTEST_SKIP() << "real data not found at " << dir << " (set STRATA_DATA_DIR)";
  const auto run = [&dir](const std::string& guess) {
    return run_strata({"register", (dir / "room_scan2.pcd").string(), (dir / "room_scan1.pcd").string(),
                       "--guess", guess, "--json"},
                      std::chrono::seconds(120));
  };
  const CommandResult degrees = run("1.79387,0.720047,0,0,0,39.7117");
  const CommandResult radians = run("1.79387 0.720047 0 0 0 0.6931");
  ASSERT_EQ(degrees.exit_code, 0) << degrees.output;
  ASSERT_EQ(radians.exit_code, 0) << radians.output;
  EXPECT_EQ(degrees.output.find("old form"), std::string::npos) << degrees.output;
  EXPECT_NE(radians.output.find("old form"), std::string::npos) << radians.output;
  const nlohmann::json a = json_of(degrees);
  const nlohmann::json b = json_of(radians);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(a["transform"][r][c].get<double>(), b["transform"][r][c].get<double>(), 1e-3)
          << r << "," << c;
  }
}

TEST(RegisterCommand, MalformedGuessIsRefused) {
  const fs::path file = private_temp_path("strata_register_guess", ".xyz");
  { std::ofstream(file) << "0 0 0\n1 0 0\n0 1 0\n"; }
  for (const std::string guess : {"1 2 3", "1,2", "1,2,x"}) {
    const CommandResult run = run_strata({"register", file.string(), file.string(), "--guess", guess});
    EXPECT_EQ(run.exit_code, 1) << guess;
    EXPECT_NE(run.output.find("x,y,z or x,y,z,roll,pitch,yaw"), std::string::npos) << run.output;
  }
  fs::remove(file);
}

}  // namespace
}  // namespace strata::testing

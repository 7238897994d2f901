#include "server/pipeline/imu_calibration_store.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

namespace strata::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr double kDegree = std::numbers::pi / 180.0;

class ImuCalibrationStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ =
        fs::temp_directory_path() / ("strata_imu_calibration_" + std::to_string(::getpid()) + "_" +
                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    file_ = directory_ / "state" / "imu-calibration.json";
  }
  void TearDown() override { fs::remove_all(directory_); }

  void write(const std::string& text) const {
    fs::create_directories(file_.parent_path());
    std::ofstream(file_, std::ios::binary) << text;
  }
  [[nodiscard]] std::string read() const {
    std::ifstream in(file_, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static PoseGraphStatus graph(std::size_t loops, double roll_deg, double pitch_deg) {
    PoseGraphStatus status;
    status.loops = loops;
    status.keyframes = 10 * loops + 5;
    status.gravity_mounting = {roll_deg * kDegree, pitch_deg * kDegree, 0.0};
    return status;
  }

  fs::path directory_;
  fs::path file_;
};

TEST_F(ImuCalibrationStoreTest, KeepsWhatLoopsConfirmedForTheNextRunOfTheSameImu) {
  {
    ImuCalibrationStore first(file_, "simulated IMU, seed 3");
    EXPECT_FALSE(first.load().has_value());
    EXPECT_EQ(first.imu_calibration().kept, ImuCalibrationStatus::Kept::kNone);
    first.update(graph(0, 0.5, -0.2));  // no loop closure yet: the estimate is the turns' alone
    EXPECT_FALSE(fs::exists(file_));
    first.update(graph(2, 0.21, -0.13));
    const ImuCalibrationStatus saved = first.imu_calibration();
    EXPECT_EQ(saved.kept, ImuCalibrationStatus::Kept::kSaved);
    ASSERT_TRUE(saved.mounting_deg.has_value());
    EXPECT_NEAR(saved.mounting_deg->x(), 0.21, 1e-9);
    EXPECT_NEAR(saved.mounting_deg->y(), -0.13, 1e-9);
    EXPECT_EQ(saved.loops, 2U);
    first.update(graph(2, 0.9, 0.9));  // no new loop: nothing new confirmed
    EXPECT_EQ(first.imu_calibration().loops, 2U);
    EXPECT_NEAR(first.imu_calibration().mounting_deg->x(), 0.21, 1e-9);
    first.update(graph(3, 0.22, -0.12));
    EXPECT_EQ(first.imu_calibration().loops, 3U);
  }
  ImuCalibrationStore second(file_, "simulated IMU, seed 3");
  const std::optional<ImuCalibration> loaded = second.load();
  ASSERT_TRUE(loaded.has_value());
  EXPECT_NEAR(loaded->mounting.x(), 0.22 * kDegree, 1e-12);
  EXPECT_NEAR(loaded->mounting.y(), -0.12 * kDegree, 1e-12);
  EXPECT_EQ(loaded->loops, 3U);
  EXPECT_EQ(loaded->keyframes, 35U);
  EXPECT_EQ(second.imu_calibration().kept, ImuCalibrationStatus::Kept::kLoaded);
  // The second run keeps its own at its first loop closure, though it has fewer than the first had.
  second.update(graph(1, 0.23, -0.11));
  EXPECT_EQ(second.imu_calibration().kept, ImuCalibrationStatus::Kept::kSaved);
  EXPECT_EQ(second.imu_calibration().loops, 1U);
}

TEST_F(ImuCalibrationStoreTest, AnotherImusCalibrationIsNotUsedAndIsReplacedAtTheFirstSave) {
  {
    ImuCalibrationStore other(file_, "simulated IMU, seed 3");
    other.update(graph(4, 0.3, 0.3));
  }
  ImuCalibrationStore store(file_, "simulated IMU, seed 4");
  EXPECT_FALSE(store.load().has_value());
  EXPECT_EQ(store.imu_calibration().kept, ImuCalibrationStatus::Kept::kNone);
  store.update(graph(1, -0.1, 0.05));
  EXPECT_EQ(parse_imu_calibration(read()).imu, "simulated IMU, seed 4");
}

TEST_F(ImuCalibrationStoreTest, ABadFileIsNotUsedAndLeftForTheNextSaveToReplace) {
  const ImuCalibration good{.imu = "imu", .mounting = {0.001, -0.002}, .loops = 2, .keyframes = 20};
  const std::string text = format_imu_calibration(good);
  const std::vector<std::string> bad = {
      "",
      "{",
      text.substr(0, text.size() / 2),
      R"({"format":"strata-imu-calibration","version":2,"imu":"imu","mounting_roll_deg":0,"mounting_pitch_deg":0,"loops":1,"keyframes":1})",
      R"({"format":-0.22,"lloops":1})",
      R"({"format":"other","version":1,"imu":"imu","mounting_roll_deg":0,"mounting_pitch_deg":0,"loops":1,"keyframes":1})",
      R"({"format":"strata-imu-calibration","version":1,"imu":"imu","mounting_roll_deg":"x","mounting_pitch_deg":0,"loops":1,"keyframes":1})",
      R"({"format":"strata-imu-calibration","version":1,"imu":"imu","mounting_roll_deg":45,"mounting_pitch_deg":0,"loops":1,"keyframes":1})",
      R"({"format":"strata-imu-calibration","version":1,"imu":"imu","mounting_roll_deg":0,"mounting_pitch_deg":0,"loops":-1,"keyframes":1})",
      R"({"format":"strata-imu-calibration","version":1,"imu":"","mounting_roll_deg":0,"mounting_pitch_deg":0,"loops":1,"keyframes":1})",
      R"({"format":"strata-imu-calibration","imu":)" + std::string(100000, '[') + std::string(100000, ']') +
          "}",
  };
  for (const std::string& contents : bad) {
    EXPECT_THROW(static_cast<void>(parse_imu_calibration(contents)), std::runtime_error) << contents;
    write(contents);
    ImuCalibrationStore store(file_, "imu");
    EXPECT_FALSE(store.load().has_value()) << contents;
    EXPECT_EQ(store.imu_calibration().kept, ImuCalibrationStatus::Kept::kNone) << contents;
    EXPECT_EQ(read(), contents) << "a file not understood is left as it is";
  }
  try {
    static_cast<void>(parse_imu_calibration(bad.back()));
    ADD_FAILURE() << "a file nested 100,000 levels deep was read";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "nested deeper than 64 levels");
  }
  const ImuCalibration parsed = parse_imu_calibration(text);
  EXPECT_EQ(parsed.imu, "imu");
  EXPECT_NEAR(parsed.mounting.x(), 0.001, 1e-15);
  EXPECT_NEAR(parsed.mounting.y(), -0.002, 1e-15);
}

TEST_F(ImuCalibrationStoreTest, ClearingForgetsItAndAStoreWithoutAnImuKeepsNothing) {
  ImuCalibrationStore store(file_, "imu");
  store.update(graph(1, 0.1, 0.1));
  ASSERT_TRUE(fs::exists(file_));
  const CommandResult cleared = store.clear_imu_calibration();
  EXPECT_TRUE(cleared.ok) << cleared.message;
  EXPECT_FALSE(fs::exists(file_));
  EXPECT_EQ(store.imu_calibration().kept, ImuCalibrationStatus::Kept::kNone);
  EXPECT_FALSE(store.imu_calibration().mounting_deg.has_value());
  EXPECT_TRUE(store.clear_imu_calibration().ok) << "nothing kept: clearing again is no error";
  store.update(graph(2, 0.1, 0.1));  // the run's next loop closure keeps its estimate again
  EXPECT_TRUE(fs::exists(file_));

  ImuCalibrationStore off;
  EXPECT_FALSE(off.load().has_value());
  off.update(graph(5, 0.1, 0.1));
  EXPECT_EQ(off.imu_calibration().kept, ImuCalibrationStatus::Kept::kOff);
  const CommandResult refused = off.clear_imu_calibration();
  EXPECT_FALSE(refused.ok);
  EXPECT_EQ(refused.code, ErrorCode::kUnavailable);
}

TEST_F(ImuCalibrationStoreTest, AFailedSaveIsTriedAgainAtTheNextOptimization) {
  // A file where the state directory should be: nothing can be written (as root too).
  fs::create_directories(directory_);
  std::ofstream(directory_ / "state") << "not a directory";
  ImuCalibrationStore store(file_, "imu");
  store.update(graph(1, 0.1, 0.2));
  EXPECT_EQ(store.imu_calibration().kept, ImuCalibrationStatus::Kept::kNone);
  fs::remove(directory_ / "state");
  store.update(graph(1, 0.1, 0.2));
  EXPECT_EQ(store.imu_calibration().kept, ImuCalibrationStatus::Kept::kSaved);
  EXPECT_EQ(parse_imu_calibration(read()).loops, 1U);
}

}  // namespace
}  // namespace strata::pipeline

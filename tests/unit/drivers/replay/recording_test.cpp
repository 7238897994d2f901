// Recording (issue #9 item 3) and replaying it: what the recorder writes reads back as the same samples and
// scans, bit for bit, and the replay driver plays them in order without losing any.
#include <gtest/gtest.h>

#include <algorithm>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "drivers/io/pcd_writer.hpp"
#include "drivers/replay/dataset.hpp"
#include "drivers/replay/mcap_recording_writer.hpp"
#include "drivers/replay/recorder.hpp"
#include "drivers/replay/reference_odometry.hpp"
#include "drivers/replay/replay_driver.hpp"

namespace strata::replay {
namespace {

namespace fs = std::filesystem;

class Recording : public testing::Test {
 public:  // the fixed run's values, for the checks outside the fixture too
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("strata_recording_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static Pose3 pose(double x, double y, double yaw, double z = 0.0) {
    Pose3 p;
    p.position = Eigen::Vector3d(x, y, z);
    p.yaw = yaw;
    p.pitch = 0.01 * x;  // values with every bit used, to catch any rounding on the way
    p.roll = 1.0 / 3.0;
    return p;
  }
  static RobotSample sample(double stamp) {
    RobotSample s;
    s.stamp = stamp;
    s.odometry = pose(stamp * 0.1, stamp / 7.0, stamp / 11.0);
    s.truth = pose(stamp * 0.1 + 1e-3, stamp / 7.0, stamp / 13.0, 0.2);
    return s;
  }
  static ScanEvent scan(double stamp, float offset) {
    ScanEvent s;
    s.stamp = stamp;
    s.duration = 1.0 / 3.0;
    s.sensor = "tilting-laser";
    s.points = {{offset, 2.0f / 3.0f, -1.0f}, {1e-7f, offset * 3.0f, 42.0f}};
    s.point_times = {-1.0f / 3.0f, -1.0f / 30.0f};  // a lidar's: replayed, they deskew as live
    s.sensor_to_base = Eigen::Translation3d(0.1, 0.0, 0.7) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
    s.odometry = sample(stamp).odometry;
    s.truth = sample(stamp).truth;
    s.rays = 5;
    s.max_range = 30.0;
    if (stamp > 0.05)  // the later scan with an IMU reading, the earlier without
      s.gravity =
          GravityReading{.up_in_base = Eigen::Vector3d(0.01, -1.0 / 3.0, 1.0).normalized(), .sigma = 0.003};
    if (stamp > 0.05)
      s.standing_gyro = StandingGyro{.rate = 1.0 / 7.0 * 1e-4, .seconds = 4.8, .sigma = 1.7e-4 / 3.0};
    return s;
  }
  /// Records 10 samples and 2 scans (at samples 3 and 7): into dir_ in the own layout, or into `mcap_file`.
  void record_run(const fs::path& mcap_file = {}) {
    const nlohmann::json metadata{{"source", "test"}, {"seed", 7}};
    const auto recorder =
        mcap_file.empty()
            ? std::make_unique<Recorder>(dir_, metadata, initial())
            : std::make_unique<Recorder>(std::make_unique<McapRecordingWriter>(mcap_file, metadata, initial(),
                                                                               mcap::Compression::kZstd),
                                         Recorder::Limits{});
    for (int i = 0; i < 10; ++i) {
      recorder->record(sample(i * 0.01));
      if (i == 3 || i == 7)
        recorder->record(scan(i * 0.01, static_cast<float>(i) / 3.0f));
    }
  }
  static Eigen::Isometry3d initial() {
    return Eigen::Translation3d(1.0 / 3.0, -2.0, 0.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  }
  /// Starts `driver` with `outputs` (its on_finished taken over), waits until everything is played (30 s at
  /// most) and stops it. False when it did not finish in time.
  static bool play_to_the_end(ReplayDriver& driver, RobotDriver::Outputs outputs) {
    std::mutex mutex;
    std::condition_variable done;
    bool finished = false;
    outputs.on_finished = [&] {
      std::lock_guard lock(mutex);
      finished = true;
      done.notify_all();
    };
    driver.start(outputs);
    bool in_time = false;
    {
      std::unique_lock lock(mutex);
      in_time = done.wait_for(lock, std::chrono::seconds(30), [&] { return finished; });
    }
    driver.stop();
    return in_time;
  }

  /// Plays `driver` as fast as it goes into `scans`; false when it did not finish in time.
  static bool play_scans(ReplayDriver& driver, std::vector<ScanEvent>& scans) {
    RobotDriver::Outputs outputs;
    outputs.on_sample = [](const RobotSample&) {};
    outputs.on_scan = [&](ScanEvent s) { scans.push_back(std::move(s)); };
    outputs.wait_for_pipeline = [] { return true; };
    return play_to_the_end(driver, outputs);
  }

  fs::path dir_;
};

/// The run record_run() recorded, as `dataset` reads it back: every number and point bit for bit.
void expect_the_recorded_run(const Dataset& dataset) {
  ASSERT_TRUE(dataset.initial_map_from_odom.has_value());
  EXPECT_EQ(dataset.initial_map_from_odom->matrix(), Recording::initial().matrix());
  ASSERT_EQ(dataset.odometry.size(), 10u);
  EXPECT_EQ(dataset.odometry[9].stamp, Recording::sample(0.09).stamp);
  EXPECT_EQ(dataset.odometry[9].odometry.position, Recording::sample(0.09).odometry.position);
  EXPECT_EQ(dataset.odometry[9].reference->yaw, Recording::sample(0.09).truth->yaw);
  ASSERT_EQ(dataset.scans.size(), 2u);
  const ScanEvent expected = Recording::scan(0.07, 7.0f / 3.0f);
  const DatasetScan& got = dataset.scans[1];
  EXPECT_EQ(got.stamp, expected.stamp);
  EXPECT_EQ(got.duration, expected.duration);
  EXPECT_EQ(got.sensor, expected.sensor);
  EXPECT_EQ(got.rays, expected.rays);
  EXPECT_EQ(got.max_range, expected.max_range);
  EXPECT_EQ(got.sensor_to_base.matrix(), expected.sensor_to_base.matrix());
  EXPECT_EQ(got.odometry->position, expected.odometry.position);
  EXPECT_EQ(got.odometry->roll, expected.odometry.roll);
  EXPECT_EQ(got.odometry->pitch, expected.odometry.pitch);
  EXPECT_EQ(got.reference->position, expected.truth->position);
  std::vector<float> times;
  EXPECT_EQ(load_points(got, &times), expected.points);
  EXPECT_EQ(times, expected.point_times);
  ASSERT_TRUE(got.gravity.has_value());
  EXPECT_EQ(got.gravity->up_in_base, expected.gravity->up_in_base);
  EXPECT_EQ(got.gravity->sigma, expected.gravity->sigma);
  EXPECT_FALSE(dataset.scans[0].gravity.has_value()) << "a scan without a reading reads back without one";
  ASSERT_TRUE(got.standing_gyro.has_value());
  EXPECT_EQ(got.standing_gyro->rate, expected.standing_gyro->rate);
  EXPECT_EQ(got.standing_gyro->seconds, expected.standing_gyro->seconds);
  EXPECT_EQ(got.standing_gyro->sigma, expected.standing_gyro->sigma);
  EXPECT_FALSE(dataset.scans[0].standing_gyro.has_value());
}

TEST_F(Recording, ReadsBackExactly) {
  record_run();
  const Dataset dataset = open_dataset(dir_);
  EXPECT_EQ(dataset.layout, DatasetLayout::kRecording);
  expect_the_recorded_run(dataset);
  std::ifstream in(dir_ / "recording.json");
  const auto metadata = nlohmann::json::parse(in);
  EXPECT_EQ(metadata["finished"], true);
  EXPECT_EQ(metadata["scans"], 2);
  EXPECT_EQ(metadata["seed"], 7);
}

TEST_F(Recording, AnMcapRecordingReadsBackExactlyAndIsFileDotPartUntilItIsFinished) {
  fs::create_directories(dir_);
  const fs::path file = dir_ / "run.mcap";
  record_run(file);
  EXPECT_FALSE(fs::exists(McapRecordingWriter::partial_path(file)));
  const Dataset dataset = open_dataset(file);
  EXPECT_EQ(dataset.layout, DatasetLayout::kMcap);
  expect_the_recorded_run(dataset);
  {
    Recorder recorder(std::make_unique<McapRecordingWriter>(dir_ / "second.mcap", nlohmann::json::object(),
                                                            initial(), mcap::Compression::kNone),
                      Recorder::Limits{});
    recorder.record(sample(0.0));
    recorder.record(scan(0.01, 1.0f));
    recorder.flush();
    EXPECT_TRUE(fs::exists(dir_ / "second.mcap.part"));
    EXPECT_FALSE(fs::exists(dir_ / "second.mcap"));
    EXPECT_THROW((void)open_dataset(McapRecordingWriter::partial_path(dir_ / "second.mcap")), DatasetError);
  }
  EXPECT_EQ(open_dataset(dir_ / "second.mcap").scans.size(), 1u);
  EXPECT_THROW((McapRecordingWriter(file, {}, initial(), mcap::Compression::kZstd)), std::runtime_error)
      << "an existing file is not overwritten";
}

TEST_F(Recording, RefusesADirectoryThatHoldsARecording) {
  record_run();
  EXPECT_THROW({ const Recorder again(dir_, {}, Eigen::Isometry3d::Identity()); }, std::runtime_error);
  EXPECT_EQ(open_dataset(dir_).scans.size(), 2u);  // untouched
}

TEST_F(Recording, AFailedWriteIsCountedAndTheRestIsRecorded) {
  fs::create_directories(dir_ / "scans" / "000000.pcd");  // the first scan's file cannot replace a directory
  {
    Recorder recorder(dir_, {}, Eigen::Isometry3d::Identity());
    recorder.record(scan(1.0, 1.0f));
    recorder.record(scan(2.0, 2.0f));
    recorder.flush();
    EXPECT_EQ(recorder.status().errors, 1u);
    EXPECT_EQ(recorder.status().scans, 1u);
  }
  // The failed scan is not listed; the one after it is, under the next free name.
  const Dataset dataset = open_dataset(dir_);
  ASSERT_EQ(dataset.scans.size(), 1u);
  EXPECT_EQ(dataset.scans[0].stamp, 2.0);
}

TEST_F(Recording, ReplayAsFastAsPossiblePlaysEverythingInOrder) {
  record_run();
  ReplayOptions options;
  options.pacing.as_fast_as_possible = true;
  ReplayDriver driver(open_dataset(dir_), options);
  EXPECT_EQ(driver.initial_map_from_odom().matrix(), initial().matrix());
  std::vector<double> sample_stamps;
  std::vector<ScanEvent> scans;
  int waits = 0;
  RobotDriver::Outputs outputs;
  outputs.on_sample = [&](const RobotSample& s) { sample_stamps.push_back(s.stamp); };
  outputs.on_scan = [&](ScanEvent s) { scans.push_back(std::move(s)); };
  outputs.wait_for_pipeline = [&] {
    ++waits;
    return true;
  };
  ASSERT_TRUE(play_to_the_end(driver, outputs));
  EXPECT_TRUE(driver.finished());
  // Every odometry sample (the scans' own come from the same samples: 10 + 2), in time order.
  EXPECT_EQ(sample_stamps.size(), 12u);
  EXPECT_TRUE(std::is_sorted(sample_stamps.begin(), sample_stamps.end()));
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(waits, 2);  // paced on the pipeline after each scan
  const ScanEvent expected = scan(0.03, 1.0f);
  EXPECT_EQ(scans[0].points, expected.points);
  EXPECT_EQ(scans[0].point_times, expected.point_times);  // deskewed as the live run was
  EXPECT_EQ(scans[0].odometry.position, expected.odometry.position);
  EXPECT_EQ(scans[0].sensor_to_base.matrix(), expected.sensor_to_base.matrix());
  EXPECT_EQ(scans[0].max_range, expected.max_range);
}

TEST_F(Recording, ReplayAtTheRecordedRatePlaysEverythingAndStops) {
  record_run();  // 0.09 s of samples: at 10x, about 10 ms
  ReplayOptions options;
  options.pacing.time_scale = 10.0;
  ReplayDriver driver(open_dataset(dir_), options);
  std::size_t samples = 0;
  std::size_t scans = 0;
  RobotDriver::Outputs outputs;
  outputs.on_sample = [&](const RobotSample&) { ++samples; };
  outputs.on_scan = [&](ScanEvent) { ++scans; };  // no wait_for_pipeline: a paced replay never waits
  ASSERT_TRUE(play_to_the_end(driver, outputs));
  EXPECT_EQ(samples, 12u);
  EXPECT_EQ(scans, 2u);
}

TEST_F(Recording, StoppingAReplayEndsItEarly) {
  record_run();
  ReplayOptions options;
  options.pacing.time_scale = 1e-4;  // 0.09 s of data would take 15 minutes
  ReplayDriver driver(open_dataset(dir_), options);
  RobotDriver::Outputs outputs;
  outputs.on_sample = [](const RobotSample&) {};
  outputs.on_scan = [](ScanEvent) {};
  driver.start(outputs);
  driver.stop();  // returns at once: the wait for the next event is interrupted
  EXPECT_FALSE(driver.finished());
}

TEST_F(Recording, OdometryFromReferencePosesIsSeededNoise) {
  record_run();
  ReplayOptions options;
  options.odometry = OdometrySource::kReference;
  const Dataset dataset = open_dataset(dir_);
  std::vector<Pose3> reference;
  for (const auto& s : dataset.scans)
    reference.push_back(*s.reference);
  // Without noise: the reference's planar part; with noise: the same for the same seed, else different.
  const auto exact = odometry_from_reference(reference, {}, 1);
  EXPECT_NEAR(exact[1].position.x(), reference[1].position.x(), 1e-12);
  EXPECT_NEAR(exact[1].yaw, reference[1].yaw, 1e-12);
  const OdometryNoise noise{0.05, 0.02};
  const auto a = odometry_from_reference(reference, noise, 7);
  const auto b = odometry_from_reference(reference, noise, 7);
  const auto c = odometry_from_reference(reference, noise, 8);
  EXPECT_EQ(a[1].position, b[1].position);
  EXPECT_NE(a[1].position, exact[1].position);
  EXPECT_NE(a[1].position, c[1].position);
  const ReplayDriver driver(dataset, options);
  EXPECT_NE(driver.description().find("odometry from reference poses"), std::string::npos)
      << driver.description();
}

TEST_F(Recording, ReferenceOdometryNeedsReferencePoses) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "a.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\n"
                                   "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
  std::ofstream(dir_ / "scans.csv") << "file,stamp,x,y,z,roll,pitch,yaw\na.pcd,0,0,0,0,0,0,0\n";
  ReplayOptions options;
  options.odometry = OdometrySource::kReference;
  EXPECT_THROW({ const ReplayDriver driver(open_dataset(dir_), options); }, DatasetError);
  options.odometry = OdometrySource::kAuto;  // the dataset's odometry
  const ReplayDriver driver(open_dataset(dir_), options);
  EXPECT_NE(driver.description().find("odometry from the dataset"), std::string::npos)
      << driver.description();
}

TEST_F(Recording, AListOfScansWithoutPosesReplaysAsALidarAlone) {
  fs::create_directories(dir_);
  const std::string pcd =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n"
      "DATA ascii\n1 2 3\n";
  std::ofstream(dir_ / "a.pcd") << pcd;
  std::ofstream(dir_ / "b.pcd") << pcd;
  std::ofstream(dir_ / "scans.csv") << "file,stamp\na.pcd,0.0\nb.pcd,0.1\n";
  ReplayOptions options;
  options.pacing.as_fast_as_possible = true;
  ReplayDriver driver(open_dataset(dir_), options);  // was: "the dataset has no reference pose ..."
  EXPECT_NE(driver.description().find("odometry from none"), std::string::npos) << driver.description();
  std::vector<ScanEvent> scans;
  ASSERT_TRUE(play_scans(driver, scans));
  // Handed on as a lidar alone's: the localizer predicts the motion from the scans (a constant odometry
  // would say the sensor stood still, and every real turn would be "too far from the guess").
  ASSERT_EQ(scans.size(), 2u);
  for (const ScanEvent& scan : scans) {
    EXPECT_FALSE(scan.has_odometry);
    EXPECT_EQ(scan.odometry.position, Eigen::Vector3d::Zero());
  }
}

TEST_F(Recording, ALidarAlonesRecordingReplaysAsALidarAlone) {
  {
    Recorder recorder(dir_, {{"source", "test"}}, initial());
    for (int i = 0; i < 2; ++i) {
      ScanEvent alone = scan(0.1 * i, 1.0f);
      alone.has_odometry = false;  // a pcap or a live lidar: its odometry is a constant
      alone.odometry = Pose3{};
      alone.truth.reset();
      recorder.record(alone);
    }
  }
  const Dataset dataset = open_dataset(dir_);
  ASSERT_EQ(dataset.scans.size(), 2u);
  EXPECT_FALSE(dataset.scans[0].odometry.has_value());  // not "standing still at the origin"
  const ReplayDriver driver(dataset, {});
  EXPECT_NE(driver.description().find("odometry from none"), std::string::npos) << driver.description();
}

TEST_F(Recording, ADatasetWithOdometryCanBeReplayedAsALidarAlone) {
  record_run();
  ReplayOptions options;
  options.odometry = OdometrySource::kNone;
  const ReplayDriver driver(open_dataset(dir_), options);
  EXPECT_NE(driver.description().find("odometry from none"), std::string::npos) << driver.description();
}

TEST_F(Recording, AScanListsReferencesWithoutAMountAreTheSensorsCarriedToTheBase) {
  // A lidar dataset: point files and the sensor's reference poses, nothing about a base. With the mount
  // (given here; estimated from the ground otherwise) the map frame and the truth are the base's, so that
  // the estimate, a base pose, compares with them.
  const std::vector<Eigen::Vector3f> points{{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  fs::create_directories(dir_);
  std::ofstream(dir_ / "a.pcd", std::ios::binary) << io::encode_binary_pcd(points);
  std::ofstream(dir_ / "b.pcd", std::ios::binary) << io::encode_binary_pcd(points);
  std::ofstream(dir_ / "scans.csv") << "file,stamp,truth_x,truth_y,truth_z,truth_roll,truth_pitch,truth_yaw\n"
                                       "a.pcd,0,1,2,1.5,0.1,0,0.3\nb.pcd,1,3,2,1.5,0.1,0,0.8\n";
  Eigen::Isometry3d sensor_to_base = Eigen::Isometry3d::Identity();
  sensor_to_base.translation() = Eigen::Vector3d(0.2, 0.0, 1.2);
  sensor_to_base.linear() = Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  ReplayOptions options;
  options.pacing.as_fast_as_possible = true;
  options.odometry = OdometrySource::kNone;
  options.mount = sensor_to_base;
  ReplayDriver driver(open_dataset(dir_), options);
  const Dataset dataset = open_dataset(dir_);
  const Eigen::Isometry3d first_base = dataset.scans[0].reference->to_isometry() * sensor_to_base.inverse();
  EXPECT_TRUE(driver.initial_map_from_odom().isApprox(first_base, 1e-9));
  std::vector<ScanEvent> scans;
  ASSERT_TRUE(play_scans(driver, scans));
  ASSERT_EQ(scans.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(scans[i].truth.has_value());
    const Eigen::Isometry3d expected = dataset.scans[i].reference->to_isometry() * sensor_to_base.inverse();
    EXPECT_TRUE(scans[i].truth->to_isometry().isApprox(expected, 1e-9)) << i;
    // The sensor, where the base's truth and the mount put it, is where the reference says.
    EXPECT_TRUE((scans[i].truth->to_isometry() * scans[i].sensor_to_base)
                    .isApprox(dataset.scans[i].reference->to_isometry(), 1e-9));
  }
}

}  // namespace
}  // namespace strata::replay

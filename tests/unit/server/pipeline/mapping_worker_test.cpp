#include "server/pipeline/mapping_worker.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/mls/mls_file.hpp"
#include "server/encoding/occupancy_png.hpp"
#include "server/encoding/tile_codec.hpp"
#include "tests/support/campus_scans.hpp"
#include "tests/support/wall_keyframes.hpp"

namespace strata::pipeline {
namespace {

namespace fs = std::filesystem;

using testing::campus_scans;

/// Where the sensor was, from the true pose (as a perfect localizer would place the scan).
Eigen::Isometry3d map_from_sensor(const ScanEvent& scan) {
  return scan.truth->to_isometry() * scan.sensor_to_base;
}

class ScratchMapsDir {
 public:
  ScratchMapsDir() {
    static std::atomic<int> counter{0};
    path_ =
        fs::temp_directory_path() /
        ("strata-mapping-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
         std::to_string(counter++) + "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
  }
  ~ScratchMapsDir() { fs::remove_all(path_); }
  ScratchMapsDir(const ScratchMapsDir&) = delete;
  ScratchMapsDir& operator=(const ScratchMapsDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string text_of(const std::vector<std::uint8_t>& bytes) {
  return {bytes.begin(), bytes.end()};
}

TEST(MappingWorker, SimulatedScansBuildTilesAndAnOccupancyAroundTheRobot) {
  ASSERT_GE(campus_scans().size(), 2U);
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  EXPECT_TRUE(fs::is_directory(dir.path())) << "the maps directory is created";
  std::vector<std::uint64_t> heard;
  std::vector<bool> started;
  worker.add_listener([&](const MapUpdate& update) {
    heard.push_back(update.version);
    started.push_back(update.drivable.start_found);
    EXPECT_EQ(update.version, update.map.version());
  });
  // The push to the map stream: told after every scan, with the new snapshot already in MapState.
  std::vector<std::uint64_t> published;
  worker.on_published([&] { published.push_back(state.snapshot() ? state.snapshot()->version : 0); });
  worker.start();
  EXPECT_EQ(state.snapshot(), nullptr) << "nothing before the first scan";

  std::shared_ptr<const MapSnapshot> previous;
  for (const ScanEvent& scan : campus_scans()) {
    worker.submit(scan, map_from_sensor(scan));
    worker.flush();
    const auto snapshot = state.snapshot();
    ASSERT_NE(snapshot, nullptr);
    if (previous) {
      EXPECT_GT(snapshot->version, previous->version);
      // Tiles the scan did not change keep their encoding: the same object.
      for (const auto& tile : snapshot->tiles)
        for (const auto& old : previous->tiles)
          if (old->tile_x == tile->tile_x && old->tile_y == tile->tile_y && old->version == tile->version) {
            EXPECT_EQ(old.get(), tile.get());
          }
    }
    previous = snapshot;
  }
  const MapSnapshot& snapshot = *state.snapshot();
  EXPECT_EQ(snapshot.version, campus_scans().size());
  EXPECT_EQ(worker.status().scans, campus_scans().size());
  ASSERT_FALSE(snapshot.tiles.empty());
  std::size_t patches = 0;
  for (std::size_t i = 0; i < snapshot.tiles.size(); ++i) {
    const EncodedTile& tile = *snapshot.tiles[i];
    if (i > 0) {
      const EncodedTile& before = *snapshot.tiles[i - 1];
      EXPECT_TRUE(before.tile_x < tile.tile_x ||
                  (before.tile_x == tile.tile_x && before.tile_y < tile.tile_y));
    }
    patches += tile.patches;
    if (!tile.draco.empty()) {
      EXPECT_EQ(encoding::decode_tile(tile.draco).size(), tile.patches);
    }
  }
  EXPECT_EQ(patches, snapshot.patches);
  EXPECT_GT(snapshot.cells, 1000U);

  ASSERT_NE(snapshot.occupancy, nullptr);
  EXPECT_EQ(snapshot.occupancy->version, snapshot.version);
  const LevelGrid occupancy = encoding::decode_occupancy_png(*snapshot.occupancy);
  const Eigen::Vector3d robot = campus_scans().back().truth->position;
  std::size_t free_near_robot = 0;
  for (int dy = -10; dy <= 10; ++dy)
    for (int dx = -10; dx <= 10; ++dx)
      if (occupancy.at_position(robot.x() + 0.1 * dx, robot.y() + 0.1 * dy) == Occupancy::free)
        ++free_near_robot;
  EXPECT_GT(free_near_robot, 100U) << "free ground within a metre of the robot";
  EXPECT_NEAR(snapshot.occupancy->level_z, robot.z(), 0.2);

  ASSERT_EQ(heard.size(), campus_scans().size());
  ASSERT_EQ(published.size(), campus_scans().size());
  for (std::size_t i = 0; i < heard.size(); ++i) {
    EXPECT_EQ(heard[i], i + 1);
    EXPECT_EQ(published[i], i + 1);
    EXPECT_TRUE(started[i]);
  }
}

TEST(MappingWorker, SavesListsLoadsAndDownloads) {
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  worker.start();
  const ScanEvent& scan = campus_scans().front();
  worker.submit(scan, map_from_sensor(scan));
  worker.flush();
  const auto mapped = state.snapshot();
  ASSERT_NE(mapped, nullptr);

  ASSERT_TRUE(worker.save_map("campus.smls").ok);
  EXPECT_TRUE(fs::exists(dir.path() / "campus.smls"));
  const std::vector<MapFileInfo> maps = worker.list_maps();
  ASSERT_EQ(maps.size(), 1U);
  EXPECT_EQ(maps[0].name, "campus.smls");
  EXPECT_EQ(maps[0].bytes, fs::file_size(dir.path() / "campus.smls"));
  EXPECT_GT(maps[0].modified, 1.6e9);

  EXPECT_EQ(text_of(worker.download("strata", std::nullopt).bytes).substr(0, 8), "STRATMLS");
  EXPECT_EQ(text_of(worker.download("ply", std::nullopt).bytes).substr(0, 3), "ply");
  const MapDownload yaml = worker.download("yaml", std::nullopt);
  EXPECT_NE(text_of(yaml.bytes).find("resolution"), std::string::npos);
  EXPECT_EQ(yaml.version, mapped->version);
  EXPECT_NE(text_of(yaml.bytes).find("format=pgm&version=" + std::to_string(yaml.version)),
            std::string::npos);
  const MapDownload pgm = worker.download("pgm", yaml.version);
  EXPECT_EQ(text_of(pgm.bytes).substr(0, 2), "P5");
  EXPECT_EQ(pgm.version, yaml.version);
  EXPECT_TRUE(worker.download("zip", std::nullopt).bytes.empty());
  const MapDownload mcap = worker.download("mcap", yaml.version);  // the drivable map of that version
  EXPECT_EQ(text_of(mcap.bytes).substr(0, 5), "\x89MCAP");
  EXPECT_EQ(mcap.version, yaml.version);

  // Another scan, then back to the saved map: its patches again, under a newer version.
  const ScanEvent& second = campus_scans()[1];
  worker.submit(second, map_from_sensor(second));
  worker.flush();
  const auto grown = state.snapshot();
  // The ROS map of the first version is kept for its YAML's reader, though the map has moved on; a
  // version never downloaded is gone.
  EXPECT_EQ(text_of(worker.download("pgm", yaml.version).bytes), text_of(pgm.bytes));
  EXPECT_TRUE(worker.download("pgm", yaml.version + 100).version_gone);
  EXPECT_GT(grown->patches, mapped->patches);
  // The map's name (a fleet's mapId is made of it): none before the save, the saved name after it.
  EXPECT_TRUE(mapped->name.empty());
  EXPECT_EQ(grown->name, "campus.smls");
  const CommandResult loaded = worker.load_map("campus.smls", MapMode::kMapping);
  ASSERT_TRUE(loaded.ok) << loaded.message;
  const auto reloaded = state.snapshot();
  EXPECT_EQ(reloaded->name, "campus.smls");
  EXPECT_GT(reloaded->version, grown->version);
  EXPECT_EQ(reloaded->patches, mapped->patches);
  // The saved map's tiles, and the tiles only the second scan made as empty ones (clients drop them).
  const auto with_patches = std::count_if(reloaded->tiles.begin(), reloaded->tiles.end(),
                                          [](const auto& tile) { return tile->patches > 0; });
  EXPECT_EQ(static_cast<std::size_t>(with_patches), mapped->tiles.size());
  EXPECT_EQ(reloaded->tiles.size(), grown->tiles.size());
  for (const auto& tile : reloaded->tiles)
    EXPECT_EQ(tile->version, reloaded->version) << "every tile is new to clients";
}

TEST(MappingWorker, RefusesBadNamesAndCorruptFilesWithoutTouchingTheMap) {
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  worker.start();
  const ScanEvent& scan = campus_scans().front();
  worker.submit(scan, map_from_sensor(scan));
  worker.flush();
  const auto before = state.snapshot();

  for (const std::string name : {"", ".", "..", "../escape", "a/b", "/etc/passwd", ".hidden", "tab\there"}) {
    const CommandResult saved = worker.save_map(name);
    EXPECT_FALSE(saved.ok) << name;
    EXPECT_EQ(saved.code, ErrorCode::kBadParams) << name;
    EXPECT_EQ(worker.load_map(name, MapMode::kMapping).code, ErrorCode::kBadParams) << name;
  }
  EXPECT_EQ(worker.load_map("missing.smls", MapMode::kMapping).code, ErrorCode::kNotFound);

  ASSERT_TRUE(worker.save_map("good.smls").ok);
  // A save names the map (and its version) in a new snapshot; the map itself is the same.
  EXPECT_EQ(state.snapshot()->version, before->version);
  EXPECT_EQ(state.snapshot()->name, "good.smls");
  EXPECT_EQ(state.snapshot()->saved_version, "1");
  const auto saved = state.snapshot();
  std::string bytes;
  {
    std::ifstream in(dir.path() / "good.smls", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  {
    std::string corrupt = bytes;
    corrupt[corrupt.size() / 2] ^= 0x10;
    std::ofstream(dir.path() / "flipped.smls", std::ios::binary) << corrupt;
    std::ofstream(dir.path() / "truncated.smls", std::ios::binary) << bytes.substr(0, bytes.size() / 3);
    std::ofstream(dir.path() / "foreign.smls", std::ios::binary) << "not a map at all";
  }
  for (const char* name : {"flipped.smls", "truncated.smls", "foreign.smls"}) {
    const CommandResult result = worker.load_map(name, MapMode::kMapping);
    EXPECT_FALSE(result.ok) << name;
    EXPECT_EQ(result.code, ErrorCode::kCorruptFile) << name;
    EXPECT_FALSE(result.message.empty());
    EXPECT_EQ(state.snapshot(), saved) << name << ": the map is untouched";
  }
  EXPECT_EQ(worker.list_maps().size(), 4U);
}

// A burst of scans (a lidar at 10 Hz while a refresh takes 200 ms: issue 58) is inserted scan by scan and
// refreshed once: every scan is mapped, none dropped, and the map published is the one a worker refreshing
// after every scan publishes.
TEST(MappingWorker, ABurstOfScansIsMappedWholeAndRefreshedOnce) {
  const std::vector<ScanEvent>& scans = campus_scans();
  ASSERT_GE(scans.size(), 3U);
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path(),
                       {.queue_capacity = scans.size(), .max_refresh_delay = std::chrono::hours(1)});
  std::size_t published = 0;
  worker.on_published([&] { ++published; });
  for (const ScanEvent& scan : scans)
    worker.submit(scan, map_from_sensor(scan));
  worker.start();
  worker.flush();
  EXPECT_EQ(worker.status().scans, scans.size());
  EXPECT_EQ(worker.status().dropped, 0U);
  EXPECT_EQ(published, 2U) << "the first scan's refresh, then one for the " << scans.size() - 1
                           << " behind it";

  ScratchMapsDir one_by_one_dir;
  MapState one_by_one_state;
  MappingWorker one_by_one(one_by_one_state, one_by_one_dir.path());
  one_by_one.start();
  for (const ScanEvent& scan : scans) {
    one_by_one.submit(scan, map_from_sensor(scan));
    one_by_one.flush();
  }
  const MapSnapshot& burst = *state.snapshot();
  const MapSnapshot& each = *one_by_one_state.snapshot();
  EXPECT_EQ(burst.version, each.version);
  EXPECT_EQ(burst.patches, each.patches);
  EXPECT_EQ(burst.cells, each.cells);
  ASSERT_EQ(burst.tiles.size(), each.tiles.size());
  for (std::size_t i = 0; i < burst.tiles.size(); ++i) {
    EXPECT_EQ(burst.tiles[i]->version, each.tiles[i]->version);
    EXPECT_EQ(burst.tiles[i]->patches, each.tiles[i]->patches);
  }
  ASSERT_TRUE(burst.occupancy && each.occupancy);
  EXPECT_EQ(burst.occupancy->version, each.occupancy->version);
  EXPECT_EQ(burst.occupancy->png, each.occupancy->png) << "the same drivable map";
}

TEST(MappingWorker, FullQueueDropsTheOldestScanAndStoppedWorkerRefusesCommands) {
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path(), {.queue_capacity = 2});
  EXPECT_EQ(worker.save_map("x.smls").code, ErrorCode::kUnavailable) << "not started";
  EXPECT_TRUE(worker.download("strata", std::nullopt).bytes.empty());
  for (int i = 0; i < 3; ++i) {
    const ScanEvent& scan = campus_scans()[static_cast<std::size_t>(i)];
    worker.submit(scan, map_from_sensor(scan));
  }
  EXPECT_EQ(worker.status().dropped, 1U);
  worker.start();
  worker.flush();
  EXPECT_EQ(worker.status().scans, 2U);
  worker.stop();
  EXPECT_EQ(worker.load_map("x.smls", MapMode::kMapping).code, ErrorCode::kNotFound);
  EXPECT_EQ(worker.save_map("x.smls").code, ErrorCode::kUnavailable);
}

// At 5x the campus demo's mapping dropped scans until two it mapped lay 2.1 m apart, and the way the robot
// drove across the bridge deck's seam was never marked (issue 58). A dropped scan's points go; where the
// robot stood does not.
TEST(MappingWorker, TheWayThroughDroppedScansIsDriven) {
  const auto floor_seen_from = [](double x) {
    ScanEvent scan;
    scan.stamp = x;
    scan.sensor_to_base = Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 1.0));
    for (double a = 3.0; a <= 5.0; a += 0.05)  // a floor ring beyond the robot: none under it
      for (double b = -1.0; b <= 1.0; b += 0.05)
        scan.points.emplace_back(static_cast<float>(a), static_cast<float>(b), -1.0F);
    return std::pair{scan, Eigen::Isometry3d(Eigen::Translation3d(x, 0.0, 1.0))};
  };
  const auto driven_along_the_way = [&](std::size_t queue_capacity) {
    ScratchMapsDir dir;
    MapState state;
    MappingWorker worker(state, dir.path(), {.queue_capacity = queue_capacity});
    for (const double x : {0.0, 1.5, 3.0}) {  // 1.5 m apart: a drive; 3 m apart: a jump
      const auto [scan, pose] = floor_seen_from(x);
      worker.submit(scan, pose);
    }
    worker.start();
    EXPECT_TRUE(worker.flush());
    const std::vector<std::uint8_t> bytes = worker.download("strata", std::nullopt).bytes;
    const MlsMap map =
        deserialize_map_file(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                             "test")
            .map;
    std::size_t driven = 0;
    for (double x = 0.05; x < 3.0; x += 0.1) {
      const std::vector<MlsPatch> patches = map.patches(map.cell_of(x, 0.0));
      driven += !patches.empty() && patches.front().driven() ? 1 : 0;
    }
    return std::pair{driven, worker.status().dropped};
  };
  const auto [driven, dropped] = driven_along_the_way(1);
  EXPECT_EQ(dropped, 2U) << "the first two scans dropped, the last one mapped";
  EXPECT_EQ(driven, 30U) << "every cell from the first place to the last";
  const auto [every_scan_driven, none_dropped] = driven_along_the_way(3);
  EXPECT_EQ(none_dropped, 0U);
  EXPECT_EQ(every_scan_driven, 30U) << "as when every scan is mapped";
}

// Faults from a sensor or a localizer gone wrong: an empty scan, a scan of NaN, infinite and absurdly far
// points, a scan at a NaN pose. None may add a patch, stop the worker or spoil the map: it maps the next
// good scan exactly as a worker that never saw them, and saves and loads it.
TEST(MappingWorker, EmptyNonFiniteAndAbsurdScansChangeNothing) {
  const ScanEvent& good = campus_scans()[0];
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  worker.start();

  ScanEvent empty = good;
  empty.points.clear();
  worker.submit(empty, map_from_sensor(good));
  ScanEvent garbage = good;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  garbage.points = {{nan, 0, 0},           {0, nan, 1},    {inf, 0, 0},    {0, -inf, 0},
                    {1e30F, 1e30F, 1e30F}, {-3e38F, 2, 0}, {2, 3e38F, -1}, {0, 0, 0}};
  worker.submit(garbage, map_from_sensor(good));
  Eigen::Isometry3d nan_pose = map_from_sensor(good);
  nan_pose.translation().x() = std::numeric_limits<double>::quiet_NaN();
  worker.submit(good, nan_pose);
  worker.flush();
  const auto after_faults = state.snapshot();
  EXPECT_TRUE(after_faults == nullptr || after_faults->patches == 0) << "garbage became map";

  worker.submit(good, map_from_sensor(good));
  worker.flush();
  MapState reference_state;
  MappingWorker reference(reference_state, dir.path() / "reference");
  reference.start();
  reference.submit(good, map_from_sensor(good));
  reference.flush();
  ASSERT_NE(state.snapshot(), nullptr);
  ASSERT_NE(reference_state.snapshot(), nullptr);
  EXPECT_GT(state.snapshot()->patches, 0U);
  EXPECT_EQ(state.snapshot()->patches, reference_state.snapshot()->patches);
  EXPECT_EQ(state.snapshot()->cells, reference_state.snapshot()->cells);
  EXPECT_EQ(worker.save_map("after-faults.smls").ok, true);
  EXPECT_EQ(worker.load_map("after-faults.smls", MapMode::kMapping).ok, true);
  EXPECT_EQ(state.snapshot()->patches, reference_state.snapshot()->patches);
}

/// The room of wall_keyframes.hpp as a driver's scan, its sensor at `map_from_base` * (0, 0, 1).
ScanEvent room_scan(double stamp) {
  ScanEvent scan;
  scan.stamp = stamp;
  scan.sensor_to_base = Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 1.0));
  for (const Eigen::Vector3d& p : strata::testing::room_seen_from_origin())
    scan.points.push_back((scan.sensor_to_base.inverse() * p).cast<float>());
  return scan;
}

std::shared_ptr<const EncodedTile> tile_at(const MapSnapshot& snapshot, double x) {
  const TileIndex index = MlsMap::tile_of({static_cast<int>(std::floor(x / 0.1)), 0});
  for (const auto& tile : snapshot.tiles)
    if (tile->tile_x == index.x && tile->tile_y == index.y)
      return tile;
  return nullptr;
}

TEST(MappingWorker, TheMapFollowsThePoseGraph) {
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  worker.start();
  // Two visits of the room; the second drifted 0.3 m, across a tile border (x = 3.2 m): the live map has
  // the wall twice, in two tiles.
  const Eigen::Isometry3d drifted(Eigen::Translation3d(0.3, 0.0, 0.0));
  const Eigen::Isometry3d sensor(Eigen::Translation3d(0.0, 0.0, 1.0));
  worker.submit(room_scan(1.0), sensor);
  worker.submit(room_scan(2.0), drifted * sensor);
  ASSERT_TRUE(worker.flush());
  const auto before = state.snapshot();
  ASSERT_NE(before, nullptr);
  ASSERT_NE(tile_at(*before, 3.3), nullptr);
  EXPECT_GT(tile_at(*before, 3.3)->patches, 0U) << "the drifted wall";

  // The pose graph put the second visit where the first was.
  const KeyframePtr first = strata::testing::room_keyframe(Eigen::Isometry3d::Identity(), 1.0);
  const KeyframePtr second = strata::testing::room_keyframe(drifted, 2.0);
  const std::vector<KeyframePose> corrected{{first, Eigen::Isometry3d::Identity()},
                                            {second, Eigen::Isometry3d::Identity()}};
  ASSERT_TRUE(worker.rebuild_from(corrected));
  const auto after = state.snapshot();
  EXPECT_GT(after->version, before->version);
  const auto emptied = tile_at(*after, 3.3);
  ASSERT_NE(emptied, nullptr) << "a tile that is gone stays as an empty one, so clients drop it";
  EXPECT_EQ(emptied->patches, 0U);
  EXPECT_TRUE(emptied->draco.empty());
  EXPECT_GT(emptied->version, before->version);
  EXPECT_GT(tile_at(*after, 3.0)->patches, 0U) << "the wall where it is";
  EXPECT_EQ(worker.status().rebuilds, 1U);
  EXPECT_EQ(state.snapshot()->rebuilds, 1U) << "the status and /metrics count it";

  EXPECT_FALSE(worker.rebuild_from(corrected)) << "nothing moved since";

  // A loaded map is not in the keyframes: a rebuild would throw it away.
  ASSERT_TRUE(worker.save_map("room").ok);
  ASSERT_TRUE(worker.load_map("room", MapMode::kMapping).ok);
  EXPECT_FALSE(worker.rebuild_from({{first, drifted}, {second, drifted}}));
  EXPECT_EQ(worker.status().rebuilds, 1U);
}

TEST(MappingWorkerNames, TheProtocolsRuleForEveryCommand) {
  // One rule (protocol::is_valid_map_name) for the WebSocket, REST and the worker: a name the worker
  // lists can be loaded, and one it refuses is refused the same way everywhere.
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  worker.start();
  const ScanEvent& scan = campus_scans().front();
  worker.submit(scan, map_from_sensor(scan));
  worker.flush();
  ASSERT_TRUE(worker.save_map("site-2024_01.smls").ok);
  EXPECT_EQ(worker.save_map(std::string(65, 'a')).code,
            ErrorCode::kBadParams);  // 255 was allowed here before
  EXPECT_EQ(worker.save_map("a/b").code, ErrorCode::kBadParams);
  EXPECT_EQ(worker.save_map(".x").code, ErrorCode::kBadParams);
  EXPECT_EQ(worker.load_map("my map.smls", MapMode::kMapping).code, ErrorCode::kBadParams);
  // A file put there by hand under a name no command accepts is not listed: it could not be loaded.
  std::filesystem::copy_file(dir.path() / "site-2024_01.smls", dir.path() / "my map.smls");
  std::filesystem::copy_file(dir.path() / "site-2024_01.smls", dir.path() / std::string(100, 'b'));
  const auto maps = worker.list_maps();
  ASSERT_EQ(maps.size(), 1U);
  EXPECT_EQ(maps[0].name, "site-2024_01.smls");
  for (const auto& map : maps)
    EXPECT_TRUE(worker.load_map(map.name, MapMode::kMapping).ok) << map.name;
}

TEST(MappingWorker, ARebuildKeepsTheScansNewerThanItsKeyframesAndMovesThemWithTheirKeyframe) {
  // The scans since the newest keyframe are in no keyframe yet (a lidar's keyframe comes every metre), and
  // the robot stands at the newest: the rebuilt map maps them again. They were mapped in the frame from
  // before the loop closure that moved the keyframe: mapped again as they were, a ramp's deck stood
  // 0.17 m above the rebuilt map's and closed the robot's way. They move with the keyframe they came after.
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  worker.start();
  const Eigen::Isometry3d sensor(Eigen::Translation3d(0.0, 0.0, 1.0));
  const Eigen::Isometry3d moved_on(Eigen::Translation3d(7.0, 0.0, 0.0));
  const KeyframePtr first = strata::testing::room_keyframe(Eigen::Isometry3d::Identity(), 1.0);
  const KeyframeAnchor after_first{first, Eigen::Isometry3d::Identity()};
  worker.submit(preprocess(room_scan(1.0), 0.3), sensor, after_first);
  worker.submit(preprocess(room_scan(2.0), 0.3), moved_on * sensor, after_first);  // far wall at x = 10 m
  ASSERT_TRUE(worker.flush());
  ASSERT_NE(tile_at(*state.snapshot(), 10.0), nullptr);
  ASSERT_EQ(tile_at(*state.snapshot(), 13.0), nullptr) << "nothing mapped beyond x = 12.8 m yet";

  // The graph put the keyframe 3.2 m on, a tile's width: the scan after it goes with it, to x = 13.2 m.
  ASSERT_TRUE(worker.rebuild_from({{first, Eigen::Isometry3d(Eigen::Translation3d(3.2, 0.0, 0.0))}}));
  const auto kept = tile_at(*state.snapshot(), 10.0);
  ASSERT_NE(kept, nullptr);
  EXPECT_GT(kept->patches, 0U) << "the scan after the keyframe is in the rebuilt map";
  const auto beyond = tile_at(*state.snapshot(), 13.0);
  ASSERT_NE(beyond, nullptr) << "the scan after the keyframe moved with it";
  EXPECT_GT(beyond->patches, 0U);
}

// A map saved with the pose graph's keyframes can be localized in: loading it so hands its points to the
// localizer and the scans after it leave it as it was. A map without them loads for mapping with a note,
// and is refused for localizing with the reason.
TEST(MappingWorker, AMapSavedWithKeyframesIsLocalizedInAndNotChanged) {
  ASSERT_GE(campus_scans().size(), 2U);
  ScratchMapsDir dir;
  MapState state;
  MappingWorker worker(state, dir.path());
  const KeyframePtr room = strata::testing::room_keyframe(Eigen::Isometry3d::Identity(), 1.0);
  worker.set_keyframe_source([&] {
    return std::vector<KeyframePose>{{room, Eigen::Isometry3d::Identity()}};
  });
  std::vector<std::shared_ptr<const LocalizationMap>> handed;
  worker.on_map_loaded([&](std::shared_ptr<const LocalizationMap> map) { handed.push_back(std::move(map)); });
  worker.start();
  const ScanEvent& first = campus_scans()[0];
  worker.submit(first, map_from_sensor(first));
  worker.flush();
  ASSERT_TRUE(worker.save_map("with.smls").ok);
  worker.set_keyframe_source({});  // before start() in the pipeline; here: what a run without keyframes saves
  ASSERT_TRUE(worker.save_map("without.smls").ok);

  const CommandResult refused = worker.load_map("without.smls", MapMode::kLocalize);
  EXPECT_EQ(refused.code, ErrorCode::kBadParams);
  EXPECT_NE(refused.message.find("no localization data"), std::string::npos) << refused.message;
  EXPECT_TRUE(handed.empty()) << "a refused load changes nothing";
  const CommandResult viewed = worker.load_map("without.smls", MapMode::kMapping);
  ASSERT_TRUE(viewed.ok) << viewed.message;
  EXPECT_NE(viewed.message.find("viewing"), std::string::npos) << viewed.message;
  ASSERT_EQ(handed.size(), 1U);
  EXPECT_EQ(handed.back(), nullptr) << "mapping: the localizer maps again";

  const CommandResult localizing = worker.load_map("with.smls", MapMode::kLocalize);
  ASSERT_TRUE(localizing.ok) << localizing.message;
  ASSERT_EQ(handed.size(), 2U);
  ASSERT_NE(handed.back(), nullptr);
  EXPECT_EQ(handed.back()->points.size(),
            make_localization_map({{room, Eigen::Isometry3d::Identity()}}).points.size());
  const auto loaded = state.snapshot();
  const ScanEvent& second = campus_scans()[1];
  worker.submit(second, map_from_sensor(second));
  worker.flush();
  const auto after = state.snapshot();
  EXPECT_EQ(after->patches, loaded->patches) << "a map localized in is not changed";
  ASSERT_EQ(after->tiles.size(), loaded->tiles.size());
  for (std::size_t i = 0; i < after->tiles.size(); ++i)
    EXPECT_EQ(after->tiles[i]->version, loaded->tiles[i]->version);
  // Saved again, it keeps the localization data it came with.
  ASSERT_TRUE(worker.save_map("again.smls").ok);
  EXPECT_TRUE(worker.load_map("again.smls", MapMode::kLocalize).ok);
  worker.stop();
}

}  // namespace
}  // namespace strata::pipeline

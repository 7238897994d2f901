#include "server/pipeline/map_store.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/localization/localization_map.hpp"
#include "core/mls/map_export.hpp"
#include "core/mls/mls_file.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata::pipeline {
namespace {

namespace fs = std::filesystem;

class MapStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ =
        fs::temp_directory_path() / ("strata_map_store_" + std::to_string(::getpid()) + "_" +
                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  static MlsMap scene_map() {
    MlsMap map;
    PointCloud cloud;
    test::add_plane(cloud, -3, 3, -2, 2, 0.0);
    test::add_vertical_face(cloud, 2.5, -2, 2.5, 2, 0.0, 1.5);
    map.insert_scan(cloud, {0, 0, 1});
    return map;
  }
  static std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static std::string text_of(const std::vector<std::uint8_t>& bytes) { return {bytes.begin(), bytes.end()}; }

  fs::path directory_;
};

TEST_F(MapStoreTest, ListsOnlyWhatLoadsByItsName) {
  const MapStore store(directory_);  // creates the directory
  const MlsMap map = scene_map();
  ASSERT_TRUE(store.save(map, nullptr, "site.smls").ok);
  std::ofstream(directory_ / ".hidden") << "x";
  std::ofstream(directory_ / std::string(65, 'a')) << "x";  // a name the API refuses
  fs::create_directories(directory_ / "folder");

  const std::vector<MapFileInfo> maps = store.list();
  ASSERT_EQ(maps.size(), 1U);
  EXPECT_EQ(maps[0].name, "site.smls");
  EXPECT_EQ(maps[0].bytes, fs::file_size(directory_ / "site.smls"));

  const MapStore::Loaded loaded = store.load("site.smls");
  ASSERT_TRUE(loaded.result.ok) << loaded.result.message;
  EXPECT_TRUE(loaded.map.same_content(map));
}

TEST_F(MapStoreTest, BadNamesMissingAndCorruptFilesSayWhich) {
  const MapStore store(directory_);
  EXPECT_EQ(store.save(scene_map(), nullptr, "../escape").code, ErrorCode::kBadParams);
  EXPECT_EQ(store.save(scene_map(), nullptr, "site.tmp.12").code, ErrorCode::kBadParams);
  EXPECT_FALSE(fs::exists(directory_ / "site.tmp.12"));
  EXPECT_EQ(store.load("nothing.smls").result.code, ErrorCode::kNotFound);
  std::ofstream(directory_ / "broken.smls") << "STRATMLS but not a map";
  const MapStore::Loaded broken = store.load("broken.smls");
  EXPECT_EQ(broken.result.code, ErrorCode::kCorruptFile);
  EXPECT_FALSE(broken.result.message.empty());
  EXPECT_EQ(broken.map.patch_count(), 0U);
}

TEST_F(MapStoreTest, DownloadsAreTheBytesTheFilesWouldHold) {
  const MapStore store(directory_);
  const MlsMap map = scene_map();
  ASSERT_TRUE(store.save(map, nullptr, "site.smls").ok);
  EXPECT_EQ(text_of(MapStore::download("strata", map, nullptr, nullptr, 3)),
            read_bytes(directory_ / "site.smls"));
  EXPECT_EQ(text_of(MapStore::download("ply", map, nullptr, nullptr, 3)), mls_ply(map));
  // With the localization data, the native download is the file a save writes: another robot localizes
  // in it (issue 63: the download had the map alone, and `--mode localize` refused it).
  LocalizationMap localization;
  localization.points = {{1.0F, 2.0F, 0.5F}, {-1.0F, 0.5F, 1.5F}};
  localization.keyframe_poses = {Eigen::Isometry3d::Identity()};
  ASSERT_TRUE(store.save(map, &localization, "localizable.smls").ok);
  const std::string downloaded = text_of(MapStore::download("strata", map, &localization, nullptr, 3));
  EXPECT_EQ(downloaded, read_bytes(directory_ / "localizable.smls"));
  const MapFile file = deserialize_map_file(downloaded, "the download");
  ASSERT_TRUE(file.localization.has_value());
  EXPECT_EQ(file.localization->points.size(), 2U);
  fs::remove(directory_ / "localizable.smls");

  const CellRegion region{map.cell_of(-3, -2), 60, 40};
  const DrivableMap drivable = compute_drivable_map(map, TraversabilityConfig{}, {0, 0, 0}, region);
  const std::string pgm = text_of(MapStore::download("pgm", map, nullptr, &drivable, 3));
  EXPECT_EQ(pgm.rfind("P5\n# strata drivable map\n60 40\n255\n", 0), 0U);
  const std::string yaml = text_of(MapStore::download("yaml", map, nullptr, &drivable, 3));
  EXPECT_NE(yaml.find("image: map.pgm"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.rfind("# strata map version 3; its image: GET /api/v1/map?format=pgm&version=3\n", 0), 0U)
      << yaml;

  // MCAP (drivers/ros2/map_messages.hpp; read whole by tests/interop/): with and without zstd.
  const std::string magic("\x89MCAP0\r\n", 8);
  const std::string mcap = text_of(MapStore::download("mcap", map, nullptr, &drivable, 3));
  const std::string plain = text_of(MapStore::download("mcap-uncompressed", map, nullptr, nullptr, 3));
  EXPECT_EQ(mcap.substr(0, 8), magic);
  EXPECT_EQ(mcap.substr(mcap.size() - 8), magic);
  EXPECT_NE(mcap.find("nav_msgs/msg/OccupancyGrid"), std::string::npos);
  EXPECT_EQ(plain.find("nav_msgs/msg/OccupancyGrid"), std::string::npos) << "no drivable map, no /map";
  EXPECT_NE(plain.find("/map_patches"), std::string::npos);
  EXPECT_TRUE(MapStore::download("mcap", MlsMap(), nullptr, &drivable, 3).empty());

  EXPECT_TRUE(MapStore::download("zip", map, nullptr, &drivable, 3).empty());
  EXPECT_TRUE(MapStore::download("pgm", map, nullptr, nullptr, 3).empty());
  EXPECT_TRUE(MapStore::download("strata", MlsMap(), nullptr, nullptr, 3).empty());
  // The saved map and the saves' versions (.versions/site.smls/1.map, 1.meta; localizable.smls's 1.*).
  EXPECT_EQ(std::distance(fs::recursive_directory_iterator(directory_), fs::recursive_directory_iterator()),
            8)
      << "a download writes no file";
}

}  // namespace
}  // namespace strata::pipeline

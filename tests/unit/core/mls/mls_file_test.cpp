#include "core/mls/mls_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/files/temporary_files.hpp"
#include "core/mls/drivable_map.hpp"
#include "core/mls/map_export.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata {
namespace {

namespace fs = std::filesystem;

class MlsFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("strata_mls_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// Two levels, a wall, negative coordinates, several tiles, patches faded by rays.
  static MlsMap scene_map() {
    MlsMap map;
    PointCloud cloud;
    test::add_plane(cloud, -7, 7, -2, 2, 0.0);
    test::add_plane(cloud, -1.5, 1.5, -5, 5, 5.0);
    test::add_vertical_face(cloud, 6.5, -2, 6.5, 2, 0.0, 2.0);
    map.insert_scan(cloud, {3, 0, 1});
    map.insert_scan(cloud, {-3, 0, 1});
    return map;
  }

  static std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
  }

  /// Loading `path` into a map that holds scene_map() throws an error naming `expected`, map untouched.
  static void expect_rejected(const fs::path& path, const std::string& expected) {
    MlsMap current = scene_map();
    try {
      load_mls_map_into(path, current);
      ADD_FAILURE() << "loaded a bad file";
    } catch (const MlsFileError& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
    }
    EXPECT_TRUE(current.same_content(scene_map()));
  }

  fs::path directory_;
};

TEST_F(MlsFileTest, SaveThenLoadGivesTheSameMap) {
  const MlsMap map = scene_map();
  ASSERT_GT(map.tile_count(), 2U);
  const fs::path path = directory_ / "map.smls";
  save_mls_map(map, path);
  const MlsMap loaded = load_mls_map(path);
  EXPECT_TRUE(loaded.same_content(map));
  EXPECT_EQ(loaded.patch_count(), map.patch_count());
  EXPECT_EQ(loaded.version(), map.version());

  MlsMap other;
  load_mls_map_into(path, other);
  EXPECT_TRUE(other.same_content(map));
  // Saving the loaded map again gives the same bytes: nothing is lost or reordered.
  save_mls_map(loaded, directory_ / "again.smls");
  EXPECT_EQ(read_bytes(path), read_bytes(directory_ / "again.smls"));
  // Atomic write: no temporary file left behind.
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(directory_))
    ++files;
  EXPECT_EQ(files, 2U);
}

TEST_F(MlsFileTest, SameContentSeesADifference) {
  MlsMap changed = scene_map();
  changed.insert_scan({{0.05, 0.05, 0.02}}, {0, 0, 1});
  EXPECT_FALSE(changed.same_content(scene_map()));
}

TEST(TemporaryFiles, OnlyTheSavesOwnNamesAreTemporaries) {
  EXPECT_EQ(temporary_path_for("/maps/site.strata").filename().string(),
            "site.strata.tmp." + std::to_string(::getpid()));
  EXPECT_EQ(temporary_file_owner("site.strata.tmp.4242"), 4242);
  EXPECT_EQ(temporary_file_owner("a.tmp.b.tmp.7"), 7);
  for (const char* name : {"site.strata", "notes.tmp", "x.tmp.", "x.tmp.12ab", "x.tmp.-3", "x.tmp.+3",
                           "x.tmp.0", ".tmp.12", "x.tmp.99999999999999999999", "x.tmp.12.bak"})
    EXPECT_FALSE(temporary_file_owner(name)) << name;
}

TEST_F(MlsFileTest, TruncatedFileIsRejectedAndTheMapUntouched) {
  const fs::path path = directory_ / "map.smls";
  save_mls_map(scene_map(), path);
  const std::string bytes = read_bytes(path);
  write_bytes(path, bytes.substr(0, bytes.size() / 2));
  expect_rejected(path, "truncated");
  write_bytes(path, bytes.substr(0, 10));
  expect_rejected(path, "not a Strata MLS map");
}

TEST_F(MlsFileTest, CorruptedFileIsRejectedAndTheMapUntouched) {
  const fs::path path = directory_ / "map.smls";
  save_mls_map(scene_map(), path);
  std::string bytes = read_bytes(path);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
  write_bytes(path, bytes);
  expect_rejected(path, "checksum");
}

TEST_F(MlsFileTest, ForeignAndMissingFilesAreRejected) {
  const fs::path path = directory_ / "notes.txt";
  write_bytes(path, "this is not a map, just some text that is long enough\n");
  expect_rejected(path, "bad magic");
  expect_rejected(directory_ / "missing.smls", "cannot open");
}

/// A file's bytes with `change` applied, then the checksum made right again: what a buggy writer (or a
/// fuzzer, tests/fuzz/mls_file_fuzz.cpp) produces, past the integrity checks.
std::string resealed(std::string bytes, std::size_t offset, const std::string& change) {
  bytes.replace(offset, change.size(), change);
  std::uint64_t hash = 0xCBF29CE484222325ULL;
  for (std::size_t i = 0; i + 8 < bytes.size(); ++i) {
    hash ^= static_cast<unsigned char>(bytes[i]);
    hash *= 0x100000001B3ULL;
  }
  bytes.replace(bytes.size() - 8, 8, std::string(reinterpret_cast<const char*>(&hash), 8));
  return bytes;
}

TEST_F(MlsFileTest, DrivenMarksSurviveTheFileAndVersion1FilesStillLoad) {
  MlsMap map;
  map.mark_driven({0.05, 0.05, 0.0});
  ASSERT_GT(map.patch_count(), 1U);
  const MlsMap loaded = deserialize_mls_map(serialize_mls_map(map), "driven.smls");
  EXPECT_TRUE(loaded.same_content(map));
  EXPECT_TRUE(loaded.patches(loaded.cell_of(0.05, 0.05))[0].driven());
  EXPECT_TRUE(loaded.patches(loaded.cell_of(0.05, 0.05))[0].on_track());
  EXPECT_FALSE(loaded.patches(loaded.cell_of(0.15, 0.05))[0].on_track());

  // One patch in one tile, written in format 4, then rewritten as format 3 (kTrack unknown to it), 2 (no
  // localization byte after the tiles) and 1 (no flags byte either): both load, the first unmarked. Patches
  // start after the header (112), the tile's x, y, version, total (20) and counts.
  MlsMap one;
  one.insert_scan({{0.05, 0.05, 0.0}}, {0, 0, 1});
  std::string bytes = serialize_mls_map(one);
  constexpr std::size_t kFlags = 112 + 20 + kMlsTileCells + 13;
  ASSERT_EQ(bytes.size(), kFlags + 1 + 1 + 8);
  EXPECT_THROW(static_cast<void>(deserialize_mls_map(resealed(bytes, kFlags, "\x80"), "bad.smls")),
               MlsFileError)
      << "a flag this build does not know";
  const auto rewritten_as = [&](std::uint32_t version) {
    const std::uint64_t size = bytes.size();
    bytes.replace(8, 4, std::string(reinterpret_cast<const char*>(&version), 4));
    bytes.replace(12, 8, std::string(reinterpret_cast<const char*>(&size), 8));
    return resealed(bytes, 0, "");
  };
  const std::string tracked = resealed(bytes, kFlags, "\x03");
  EXPECT_TRUE(deserialize_mls_map(tracked, "tracked.smls").patches(one.cell_of(0.05, 0.05))[0].on_track());
  bytes = tracked;
  EXPECT_THROW(static_cast<void>(deserialize_mls_map(rewritten_as(3), "format3.smls")), MlsFileError)
      << "format 3 knew no track";
  bytes = resealed(bytes, kFlags, std::string(1, '\0'));
  EXPECT_EQ(deserialize_map_file(rewritten_as(3), "format3.smls").format_version, 3U);
  bytes.erase(kFlags + 1, 1);
  const MapFile format2 = deserialize_map_file(rewritten_as(2), "format2.smls");
  EXPECT_TRUE(format2.map.same_content(one));
  EXPECT_EQ(format2.format_version, 2U);
  EXPECT_FALSE(format2.localization);
  bytes.erase(kFlags, 1);
  const MlsMap old = deserialize_mls_map(rewritten_as(1), "old.smls");
  EXPECT_TRUE(old.same_content(one));
  try {
    static_cast<void>(deserialize_mls_map(rewritten_as(5), "new.smls"));
    ADD_FAILURE() << "loaded a format from the future";
  } catch (const MlsFileError& error) {
    EXPECT_NE(std::string(error.what()).find("reads 1 to 4"), std::string::npos) << error.what();
  }
}

// What localizing in a saved map needs comes back as it went in, and a lying count is refused before it
// allocates anything.
TEST_F(MlsFileTest, TheLocalizationMapSurvivesTheFile) {
  const MlsMap map = scene_map();
  LocalizationMap localization;
  localization.voxel = 0.1;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(1.5, -2.0, 0.3);
  pose.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.1, 0.2, 1.0).normalized()).toRotationMatrix();
  localization.keyframe_poses = {Eigen::Isometry3d::Identity(), pose};
  localization.points = {{1.0F, 2.0F, 3.0F}, {-4.5F, 0.25F, 1e3F}};
  const fs::path path = directory_ / "with_localization.smls";
  save_map_file(map, &localization, path);
  const MapFile loaded = load_map_file(path);
  EXPECT_EQ(loaded.format_version, map_file_format_version());
  EXPECT_TRUE(loaded.map.same_content(map));
  ASSERT_TRUE(loaded.localization);
  EXPECT_EQ(loaded.localization->voxel, 0.1);
  EXPECT_EQ(loaded.localization->points, localization.points);
  ASSERT_EQ(loaded.localization->keyframe_poses.size(), 2U);
  EXPECT_TRUE(loaded.localization->keyframe_poses[1].isApprox(pose, 1e-12));

  save_mls_map(map, directory_ / "without.smls");
  EXPECT_FALSE(load_map_file(directory_ / "without.smls").localization);

  // The point count (the last 8 bytes before the points and the checksum) claims far more than is there.
  const std::string bytes = read_bytes(path);
  const std::size_t count_at = bytes.size() - 8 - 2 * 12 - 8;
  const std::uint64_t lie = std::uint64_t{1} << 60;
  write_bytes(directory_ / "lying.smls",
              resealed(bytes, count_at, std::string(reinterpret_cast<const char*>(&lie), 8)));
  try {
    static_cast<void>(load_map_file(directory_ / "lying.smls"));
    ADD_FAILURE() << "loaded a lying count";
  } catch (const MlsFileError& error) {
    EXPECT_NE(std::string(error.what()).find("localization map's points"), std::string::npos) << error.what();
  }
}

// Found by fuzzing: a tile index whose cells overflow int (undefined behaviour computing the cell index).
TEST_F(MlsFileTest, TileIndexOutOfRangeIsRejected) {
  const std::string bytes = serialize_mls_map(scene_map());
  constexpr std::size_t kFirstTileX = 112;  // header 20, config 72, tile bits 4, version 8, tile count 8
  const std::int32_t huge = -268435457;     // * 32 overflows
  const std::string bad = resealed(bytes, kFirstTileX, std::string(reinterpret_cast<const char*>(&huge), 4));
  try {
    static_cast<void>(deserialize_mls_map(bad, "bad.smls"));
    ADD_FAILURE() << "loaded a tile index that overflows";
  } catch (const MlsFileError& error) {
    EXPECT_NE(std::string(error.what()).find("out of range"), std::string::npos) << error.what();
  }
  // The resealing itself is sound: the unchanged bytes load.
  EXPECT_TRUE(deserialize_mls_map(resealed(bytes, 0, ""), "good.smls").same_content(scene_map()));
}

// A file whose tiles lie far apart would make the load build dense grids over the space between (issue 59
// item 6: one tile 60 million tiles away, and one 150 tiles away that took 0.94 GB): refused as read.
TEST_F(MlsFileTest, AMapSpanningMoreThanAMapMayIsRejected) {
  MlsMap far = scene_map();
  MlsPatch patch;
  patch.mean = 0.0F;
  patch.evidence = 1;
  ASSERT_TRUE(far.append_patch({200 * kMlsTileSize, 200 * kMlsTileSize}, patch));  // 640 m away
  try {
    static_cast<void>(deserialize_mls_map(serialize_mls_map(far), "far.smls"));
    ADD_FAILURE() << "loaded a map 640 m across";
  } catch (const MlsFileError& error) {
    EXPECT_NE(std::string(error.what()).find("the map spans"), std::string::npos) << error.what();
  }
  const std::string bytes = serialize_mls_map(scene_map());
  constexpr std::size_t kFirstTileX = 112;
  const std::int32_t sixty_million = 60'000'000;
  try {
    static_cast<void>(deserialize_mls_map(
        resealed(bytes, kFirstTileX, std::string(reinterpret_cast<const char*>(&sixty_million), 4)),
        "x.smls"));
    ADD_FAILURE() << "loaded a tile 60 million tiles away";
  } catch (const MlsFileError& error) {
    EXPECT_NE(std::string(error.what()).find("the map spans"), std::string::npos) << error.what();
  }
  // Up to the bound is fine: 150 m across.
  MlsMap wide = scene_map();
  ASSERT_TRUE(wide.append_patch({1500, 0}, patch));
  EXPECT_TRUE(deserialize_mls_map(serialize_mls_map(wide), "wide.smls").same_content(wide));
}

TEST_F(MlsFileTest, ExportsRosMapAndPly) {
  const MlsMap map = scene_map();
  const CellRegion region{map.cell_of(-7, -5), 140, 100};
  const DrivableMap drivable = compute_drivable_map(map, TraversabilityConfig{}, {0, 0, 0}, region);
  const fs::path pgm = write_ros_map(drivable.grid, directory_ / "drivable.yaml");
  EXPECT_EQ(pgm, directory_ / "drivable.pgm");
  const std::string image = read_bytes(pgm);
  const std::string header = "P5\n# strata drivable map\n140 100\n255\n";
  ASSERT_EQ(image.substr(0, header.size()), header);
  ASSERT_EQ(image.size(), header.size() + 140U * 100U);
  // (0.05, 0.05) is free: column 70, row 50 from the bottom, so image row 100 - 1 - 50.
  EXPECT_EQ(static_cast<unsigned char>(image[header.size() + 49U * 140U + 70U]), 254);
  // (0.05, 4.05) is only the deck, overhead: at the road's level nothing is known there.
  EXPECT_EQ(static_cast<unsigned char>(image[header.size() + 9U * 140U + 70U]), 205);
  const std::string yaml = read_bytes(directory_ / "drivable.yaml");
  EXPECT_NE(yaml.find("image: drivable.pgm"), std::string::npos);
  EXPECT_NE(yaml.find("resolution: 0.1"), std::string::npos);
  EXPECT_NE(yaml.find("origin: [-7, -5, 0.0]"), std::string::npos) << yaml;

  write_mls_ply(map, directory_ / "map.ply");
  const std::string ply = read_bytes(directory_ / "map.ply");
  EXPECT_NE(ply.find("element vertex " + std::to_string(map.patch_count()) + "\n"), std::string::npos);
  const std::size_t body = ply.find("end_header\n") + 11;
  EXPECT_EQ(
      static_cast<std::size_t>(std::count(ply.begin() + static_cast<std::ptrdiff_t>(body), ply.end(), '\n')),
      map.patch_count());
}

}  // namespace
}  // namespace strata

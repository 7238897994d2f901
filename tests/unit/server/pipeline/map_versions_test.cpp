// The map server's immutable versions (issue 61 item 3): every save is a version with its SHA-256, the same
// bytes are the same version, a received version is checked whole before it is stored, and nothing is
// stored or changed by a refusal.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/localization/localization_map.hpp"
#include "core/mls/mls_file.hpp"
#include "server/pipeline/file_hash.hpp"
#include "server/pipeline/map_store.hpp"
#include "tests/unit/core/mls/mls_scenes.hpp"

namespace strata::pipeline {
namespace {

namespace fs = std::filesystem;

class MapVersionsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ =
        fs::temp_directory_path() / ("strata_map_versions_" + std::to_string(::getpid()) + "_" +
                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    PointCloud cloud;
    test::add_plane(cloud, -3, 3, -2, 2, 0.0);
    map_.insert_scan(cloud, {0, 0, 1});
    localization_.points = {{1.0F, 2.0F, 0.5F}};
    Eigen::Isometry3d upstairs = Eigen::Isometry3d::Identity();
    upstairs.translation() = Eigen::Vector3d(4.0, 0.0, 3.04);
    localization_.keyframe_poses = {Eigen::Isometry3d::Identity(), upstairs};
  }
  void TearDown() override { fs::remove_all(directory_); }
  static std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  fs::path directory_;
  MlsMap map_;
  LocalizationMap localization_;
};

TEST(FileHash, IsSha256) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST_F(MapVersionsTest, EverySaveIsAVersionAndTheSameBytesTheSameVersion) {
  const MapStore store(directory_);
  std::string version;
  ASSERT_TRUE(store.save(map_, &localization_, "yard.smls", &version).ok);
  EXPECT_EQ(version, "1");
  ASSERT_TRUE(store.save(map_, &localization_, "yard.smls", &version).ok);
  EXPECT_EQ(version, "1") << "unchanged: no new version";
  ASSERT_TRUE(store.save(map_, nullptr, "yard.smls", &version).ok);
  EXPECT_EQ(version, "2");

  const auto versions = store.versions().list();
  ASSERT_EQ(versions.size(), 2U);
  const MapVersionFile first = store.versions().read("yard.smls", "1");
  ASSERT_TRUE(first.result.ok) << first.result.message;
  EXPECT_EQ(first.bytes, serialize_map_file(map_, &localization_));
  EXPECT_EQ(versions[0].sha256, sha256_hex(first.bytes));
  EXPECT_EQ(versions[0].heights, (std::vector<double>{0.0, 3.0}));  // where its robot drove
  // The saved map is the newest version's bytes, and loading it names that version.
  EXPECT_EQ(read_bytes(directory_ / "yard.smls"), store.versions().read("yard.smls", "2").bytes);
  EXPECT_EQ(store.load("yard.smls").version, "2");
  EXPECT_EQ(store.load_version("yard.smls", "1").version, "1");
  // Versions are not maps of the listing (a hidden directory).
  ASSERT_EQ(store.list().size(), 1U);
}

TEST_F(MapVersionsTest, AReceivedVersionIsCheckedWholeAndRefusalsStoreNothing) {
  const MapStore store(directory_);
  const std::string bytes = serialize_map_file(map_, &localization_);
  const std::string hash = sha256_hex(bytes);
  EXPECT_EQ(store.add_version("yard.smls", "7", bytes, std::string(64, '0')).code, ErrorCode::kBadParams);
  std::string damaged = bytes;
  damaged[damaged.size() / 2] ^= 0x5a;
  EXPECT_EQ(store.add_version("yard.smls", "7", damaged, sha256_hex(damaged)).code, ErrorCode::kCorruptFile);
  EXPECT_EQ(store.add_version("yard.smls", "7", bytes.substr(0, 100), "").code, ErrorCode::kCorruptFile);
  const std::string no_localization = serialize_map_file(map_, nullptr);
  EXPECT_EQ(store.add_version("yard.smls", "7", no_localization, "").code, ErrorCode::kCorruptFile);
  EXPECT_EQ(store.add_version("yard.smls", "../7", bytes, hash).code, ErrorCode::kBadParams);
  EXPECT_TRUE(store.versions().list().empty());
  EXPECT_TRUE(store.list().empty());

  std::string upper = hash;
  for (char& c : upper)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  ASSERT_TRUE(store.add_version("yard.smls", "7", bytes, upper).ok);
  EXPECT_EQ(store.add_version("yard.smls", "7", bytes, hash).code, ErrorCode::kBadParams) << "never replaced";
  EXPECT_TRUE(store.list().empty()) << "stored as a version only: no saved map changed";
  const MapStore::Loaded loaded = store.load_version("yard.smls", "7");
  ASSERT_TRUE(loaded.result.ok) << loaded.result.message;
  EXPECT_EQ(loaded.version, "7");
  EXPECT_EQ(store.versions().next_number("yard.smls"), "8");
  EXPECT_TRUE(store.versions().remove("yard.smls", "7"));
  EXPECT_FALSE(store.versions().remove("yard.smls", "7"));
  EXPECT_EQ(store.load_version("yard.smls", "7").result.code, ErrorCode::kNotFound);
}

}  // namespace
}  // namespace strata::pipeline

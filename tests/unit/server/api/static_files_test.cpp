#include "server/api/static_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace strata::api {
namespace {

class StaticFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::path(::testing::TempDir()) / ("strata-static-" + std::to_string(::getpid()));
    std::filesystem::create_directories(root_ / "assets");
    std::ofstream(root_ / "index.html") << "<html>";
    std::ofstream(root_ / "assets" / "app.js") << "js";
    std::ofstream(root_.parent_path() / "secret.txt") << "secret";
  }
  void TearDown() override { std::filesystem::remove_all(root_); }
  std::filesystem::path root_;
};

TEST_F(StaticFiles, RootMapsToIndex) {
  EXPECT_EQ(resolve_static_path(root_, "/"), root_ / "index.html");
  EXPECT_EQ(resolve_static_path(root_, "/assets/app.js"), root_ / "assets" / "app.js");
  EXPECT_EQ(resolve_static_path(root_, "/./assets//app.js"), root_ / "assets" / "app.js");
}

TEST_F(StaticFiles, RefusesToLeaveTheRoot) {
  EXPECT_FALSE(resolve_static_path(root_, "/../secret.txt"));
  EXPECT_FALSE(resolve_static_path(root_, "/assets/../../secret.txt"));
  EXPECT_FALSE(resolve_static_path(root_, "/%2e%2e/secret.txt"));
  EXPECT_FALSE(resolve_static_path(root_, "/..\\secret.txt"));
  EXPECT_FALSE(resolve_static_path(root_, "relative"));
  EXPECT_FALSE(resolve_static_path(root_, ""));
  EXPECT_FALSE(resolve_static_path(root_, std::string_view("/index.html\0x", 13)));
}

TEST_F(StaticFiles, MissingFilesAreNotFound) {
  EXPECT_FALSE(resolve_static_path(root_, "/nope.js"));
  EXPECT_FALSE(resolve_static_path(root_, "/assets/"));  // a directory without index.html
}

TEST(MimeType, KnowsTheWebAppsFiles) {
  EXPECT_EQ(mime_type("a/index.html"), "text/html; charset=utf-8");
  EXPECT_EQ(mime_type("x.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(mime_type("x.wasm"), "application/wasm");
  EXPECT_EQ(mime_type("x.unknown"), "application/octet-stream");
}

}  // namespace
}  // namespace strata::api

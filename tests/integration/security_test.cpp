// Who may open the WebSocket, and how many: the Origin policy against cross-site WebSocket hijacking and the
// WebSocket client limit, on the real server with real clients (proto/PROTOCOL.md "Who may do what",
// "Limits").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "core/mls/mls_file.hpp"
#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

constexpr const char* kKiosk = "https://kiosk.example:8443";

class OriginPolicy : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new ServerProcess({"--scanner", "none", "--allowed-origins", kKiosk});
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static std::string own_origin() { return "http://127.0.0.1:" + std::to_string(port()); }
  static inline ServerProcess* server_ = nullptr;
};

TEST_F(OriginPolicy, ScriptsWithoutAnOriginAndTheServedAppConnect) {
  WsClient script(port());
  EXPECT_EQ(script.read()["op"], "hello");
  // The web app the server serves: its page's origin is the server itself.
  WsClient app(port(), "strata.v1", "/ws", {}, own_origin());
  EXPECT_EQ(app.read()["role"], "viewer");
  auto app_operator =
      std::make_unique<WsClient>(port(), "strata.v1, strata.token." + std::string(kTestOperatorToken), "/ws",
                                 std::string(), own_origin());
  EXPECT_EQ(app_operator->read()["role"], "operator");
}

TEST_F(OriginPolicy, APageFromAnotherSiteIsRefusedEvenWithTheToken) {
  const auto refused = websocket_upgrade(port(), {{http::field::origin, "https://evil.example"}});
  EXPECT_EQ(refused.result(), http::status::forbidden);
  const auto body = nlohmann::json::parse(refused.body());
  expect_schema("rest", "error", body);
  EXPECT_EQ(body["error"]["code"], "forbidden");
  // Knowing the token does not help a foreign page: it is refused before the token is looked at.
  const auto with_token = websocket_upgrade(
      port(),
      {{http::field::origin, "https://evil.example"},
       {http::field::sec_websocket_protocol, "strata.v1, strata.token." + std::string(kTestOperatorToken)}});
  EXPECT_EQ(with_token.result(), http::status::forbidden);
  // Same host name, other port: another origin.
  EXPECT_EQ(websocket_upgrade(port(), {{http::field::origin, "http://127.0.0.1:1"}}).result(),
            http::status::forbidden);
  // Sandboxed frames and file:// pages send "null".
  EXPECT_EQ(websocket_upgrade(port(), {{http::field::origin, "null"}}).result(), http::status::forbidden);
  EXPECT_THROW(WsClient(port(), "strata.v1", "/ws", {}, "https://evil.example"), beast::system_error);
  const auto metrics = http_get(port(), "/metrics").body();
  EXPECT_EQ(metrics.find("strata_ws_refused_origin_total 0\n"), std::string::npos) << metrics;
}

TEST_F(OriginPolicy, AnAllowedOriginConnects) {
  WsClient kiosk(port(), "strata.v1", "/ws", {}, kKiosk);
  EXPECT_EQ(kiosk.read()["op"], "hello");
  WsClient upper_case(port(), "strata.v1", "/ws", {}, "HTTPS://KIOSK.EXAMPLE:8443");
  EXPECT_EQ(upper_case.read()["op"], "hello");
}

TEST(OriginOption, AMalformedOriginIsRefusedAtStart) {
  const auto result = run_strata({"serve", "--port", "0", "--allowed-origins", "kiosk.example"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("kiosk.example"), std::string::npos) << result.output;
}

TEST(ClientLimit, OneClientOverTheLimitGets503UntilOneLeaves) {
  ServerProcess server({"--scanner", "none", "--max-clients", "2"});
  auto first = std::make_unique<WsClient>(server.port());
  first->read_op("hello");
  WsClient second(server.port());
  second.read_op("hello");

  const auto refused = websocket_upgrade(server.port(), {});
  EXPECT_EQ(refused.result(), http::status::service_unavailable);
  const auto body = nlohmann::json::parse(refused.body());
  expect_schema("rest", "error", body);
  EXPECT_EQ(body["error"]["code"], "unavailable");
  EXPECT_NE(body["error"]["message"].get<std::string>().find("at most 2"), std::string::npos) << body;
  EXPECT_THROW(WsClient{server.port()}, beast::system_error);
  // Plain HTTP is not limited by it.
  EXPECT_EQ(http_get(server.port(), "/healthz").result(), http::status::ok);

  // Once a client has gone, its place is free again (the server notices the close asynchronously).
  first.reset();
  bool connected = false;
  for (int attempt = 0; attempt < 200 && !connected; ++attempt) {
    try {
      WsClient again(server.port());
      connected = again.read()["op"] == "hello";
    } catch (const beast::system_error&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
  }
  EXPECT_TRUE(connected);
  const auto metrics = http_get(server.port(), "/metrics").body();
  EXPECT_EQ(metrics.find("strata_ws_refused_full_total 0\n"), std::string::npos) << metrics;
  second.read_op("pose");  // the clients that were in were not disturbed
}

TEST(MapsDirectory, LinksInItAreNeitherListedNorLoaded) {
  // Links in the maps directory (issue 59 item 9): one to /etc/passwd was listed to anyone with its size
  // and date, one to a file elsewhere was loaded (and then downloadable without a token).
  const std::filesystem::path maps = private_temp_path("strata-links", "");
  std::filesystem::create_directories(maps);
  const std::filesystem::path outside = private_temp_path("strata-outside", ".strata");
  std::ofstream(outside) << "not a map, and not in the maps directory";
  std::filesystem::create_symlink("/etc/passwd", maps / "passwd.strata");
  std::filesystem::create_symlink(outside, maps / "outside.strata");
  ServerProcess server({"--scanner", "none", "--maps-dir", maps.string()});
  const auto listed = nlohmann::json::parse(http_get(server.port(), "/api/v1/maps").body());
  EXPECT_TRUE(listed["maps"].empty()) << listed.dump();
  for (const char* name : {"outside.strata", "passwd.strata"}) {
    const auto load = http_request(server.port(), http::verb::post,
                                   std::string("/api/v1/maps/") + name + "/load", "", kTestOperatorToken);
    EXPECT_EQ(load.result(), http::status::not_found) << name << ": " << load.body();
  }
  EXPECT_EQ(server.stop(), 0);
  std::filesystem::remove_all(maps);
  std::filesystem::remove(outside);
}

TEST(MapsDirectory, AMapSpanningTooFarIsRefusedAndTheLiveMapStays) {
  // Issue 59 item 6: a checksummed file with one tile 60 million tiles away answered 500, yet became the
  // live map, and every scan after failed on it. It is refused as read (422), before anything changes.
  const std::filesystem::path maps = private_temp_path("strata-far", "");
  std::filesystem::create_directories(maps);
  MlsPatch patch;
  patch.evidence = 1;
  MlsMap small;
  ASSERT_TRUE(small.append_patch({0, 0}, patch));
  save_map_file(small, nullptr, maps / "small.strata");
  MlsMap far;
  ASSERT_TRUE(far.append_patch({0, 0}, patch));
  ASSERT_TRUE(far.append_patch({200 * kMlsTileSize, 200 * kMlsTileSize}, patch));
  save_map_file(far, nullptr, maps / "far.strata");
  ServerProcess server({"--scanner", "none", "--maps-dir", maps.string()});
  const auto load = [&](const std::string& name) {
    return http_request(server.port(), http::verb::post, "/api/v1/maps/" + name + "/load",
                        R"({"mode":"mapping"})", kTestOperatorToken);
  };
  ASSERT_EQ(load("small.strata").result(), http::status::ok);
  const std::string before = http_get(server.port(), "/api/v1/map?format=strata").body();
  const auto refused = load("far.strata");
  EXPECT_EQ(refused.result(), http::status::unprocessable_entity) << refused.body();
  EXPECT_NE(refused.body().find("the map spans 643 by 643 m: more than the 25 million cells"),
            std::string::npos)
      << refused.body();
  EXPECT_EQ(http_get(server.port(), "/api/v1/map?format=strata").body(), before) << "the live map changed";
  EXPECT_EQ(load("small.strata").result(), http::status::ok);
  EXPECT_EQ(server.stop(), 0);
  std::filesystem::remove_all(maps);
}

}  // namespace
}  // namespace strata::testing

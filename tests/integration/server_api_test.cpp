// The real strata process over real HTTP: health, info, pose, static files, errors, lifecycle.
#include <gtest/gtest.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

class ServerApi : public ::testing::Test {
 protected:
  // No scanner: the robot drives from the start (stop-and-go scanning is the WebSocket suite's business).
  static void SetUpTestSuite() { server_ = new ServerProcess({"--time-scale", "4", "--scanner", "none"}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static ServerProcess* server_;
};
ServerProcess* ServerApi::server_ = nullptr;

TEST_F(ServerApi, HealthzIsOk) {
  const auto response = http_get(port(), "/healthz");
  EXPECT_EQ(response.result(), http::status::ok);
  expect_schema("rest", "health", nlohmann::json::parse(response.body()));
}

TEST_F(ServerApi, InfoNamesServerAndProtocol) {
  const auto response = http_get(port(), "/api/v1/info");
  ASSERT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(response[http::field::content_type], "application/json");
  const auto info = nlohmann::json::parse(response.body());
  expect_schema("rest", "info", info);
  EXPECT_EQ(info["name"], "strata");
  EXPECT_EQ(info["protocol"], "strata.v1");
  EXPECT_EQ(info["protocol_version"], 1);
  EXPECT_FALSE(info["version"].get<std::string>().empty());
}

TEST_F(ServerApi, PoseChangesOverTime) {
  const auto first = nlohmann::json::parse(http_get(port(), "/api/v1/pose").body());
  expect_schema("rest", "pose", first);
  for (const char* key : {"x", "y", "z", "roll", "pitch", "yaw", "stamp"}) {
    ASSERT_TRUE(first.contains(key) && first[key].is_number()) << key;
  }
  // The simulated robot drives its loop; poll until its pose has moved (bounded, not timed).
  nlohmann::json later = first;
  for (int attempt = 0; attempt < 1200; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    later = nlohmann::json::parse(http_get(port(), "/api/v1/pose").body());
    if (later["stamp"] > first["stamp"] && (later["x"] != first["x"] || later["y"] != first["y"]))
      break;
  }
  EXPECT_GT(later["stamp"].get<double>(), first["stamp"].get<double>());
  EXPECT_TRUE(later["x"] != first["x"] || later["y"] != first["y"]) << later.dump();
}

TEST_F(ServerApi, ServesTheWebApp) {
  const auto response = http_get(port(), "/");
  if (response.result() == http::status::not_found)
    GTEST_SKIP() << "web bundle not built (STRATA_BUILD_WEB=OFF)";
  ASSERT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(response[http::field::content_type], "text/html; charset=utf-8");
  EXPECT_NE(response.body().find("<title>Strata</title>"), std::string::npos);
  // Issue 59 item 12: the page loads from this server alone and no other site may frame it.
  const std::string policy(response["Content-Security-Policy"]);
  EXPECT_NE(policy.find("default-src 'self'"), std::string::npos) << policy;
  EXPECT_NE(policy.find("frame-ancestors 'none'"), std::string::npos) << policy;
  EXPECT_EQ(response[http::field::x_frame_options], "DENY");
  EXPECT_EQ(response["X-Content-Type-Options"], "nosniff");
}

TEST_F(ServerApi, EveryResponseSaysItsTypeIsWhatItIs) {
  EXPECT_EQ(http_get(port(), "/api/v1/info")["X-Content-Type-Options"], "nosniff");
  EXPECT_EQ(http_get(port(), "/api/v1/no-such-thing")["X-Content-Type-Options"], "nosniff");
  EXPECT_EQ(http_get(port(), "/api/v1/info")["Content-Security-Policy"], "") << "for pages only";
}

TEST_F(ServerApi, SimWorldMatchesItsSchema) {
  const auto response = http_get(port(), "/api/v1/sim/world");
  ASSERT_EQ(response.result(), http::status::ok);
  expect_schema("rest", "sim_world", nlohmann::json::parse(response.body()));
}

TEST_F(ServerApi, UnknownEndpointIsA404WithACode) {
  const auto response = http_get(port(), "/api/v1/does-not-exist");
  EXPECT_EQ(response.result(), http::status::not_found);
  expect_schema("rest", "error", nlohmann::json::parse(response.body()));
  EXPECT_EQ(nlohmann::json::parse(response.body())["error"]["code"], "not_found");
}

TEST_F(ServerApi, WrongMethodIsA405WithACode) {
  const auto response = http_request(port(), http::verb::post, "/api/v1/pose", R"({"x":1})");
  EXPECT_EQ(response.result(), http::status::method_not_allowed);
  EXPECT_EQ(response[http::field::allow], "GET, HEAD");
  expect_schema("rest", "error", nlohmann::json::parse(response.body()));
  EXPECT_EQ(nlohmann::json::parse(response.body())["error"]["code"], "method_not_allowed");
}

TEST_F(ServerApi, PathTraversalIsRefused) {
  for (const char* target : {"/../CMakeCache.txt", "/web/../../CMakeCache.txt", "/%2e%2e/CMakeCache.txt"}) {
    EXPECT_EQ(http_get(port(), target).result(), http::status::not_found) << target;
  }
}

TEST_F(ServerApi, GarbageRequestDoesNotHurtTheServer) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  socket.connect({boost::asio::ip::make_address("127.0.0.1"), port()});
  boost::asio::write(socket, boost::asio::buffer(std::string("\x01\x02 NOT HTTP\r\n\r\n", 16)));
  beast::error_code error;
  socket.shutdown(tcp::socket::shutdown_send, error);
  char sink[256];
  while (!error)
    socket.read_some(boost::asio::buffer(sink), error);  // the server closes it
  EXPECT_EQ(http_get(port(), "/healthz").result(), http::status::ok);
}

/// Sends `bytes` on a connection of its own and returns all the server answers before it closes.
std::string raw_exchange(std::uint16_t port, const std::string& bytes) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  socket.connect({boost::asio::ip::make_address("127.0.0.1"), port});
  boost::asio::write(socket, boost::asio::buffer(bytes));
  beast::error_code error;
  socket.shutdown(tcp::socket::shutdown_send, error);
  std::string answer;
  char chunk[4096];
  while (!error)
    answer.append(chunk, socket.read_some(boost::asio::buffer(chunk), error));
  return answer;
}

TEST_F(ServerApi, MalformedRequestsGetAStatusSayingWhy) {
  // Issue 59 item 11: these were closed without an answer, and two Host headers were taken (the first).
  const std::string host = "Host: 127.0.0.1\r\n";
  const auto expect_status = [&](const std::string& request, const std::string& status,
                                 const std::string& why) {
    const std::string answer = raw_exchange(port(), request);
    EXPECT_TRUE(answer.starts_with("HTTP/1.1 " + status)) << why << ": " << answer.substr(0, 200);
    EXPECT_NE(answer.find("\"bad_request\""), std::string::npos) << why << ": " << answer;
  };
  expect_status("GET /healthz HTTP/1.1\r\n" + host + "X-Big: " + std::string(20'000, 'a') + "\r\n\r\n", "431",
                "headers over 16 KiB");
  expect_status("POST /api/v1/goal HTTP/1.1\r\n" + host + "Content-Length: 2000000\r\n\r\n", "413",
                "a body over 1 MiB");
  expect_status("POST /api/v1/goal HTTP/1.1\r\n" + host + "Content-Length: 1x\r\n\r\n", "400",
                "a bad Content-Length");
  expect_status("GET /healthz HTTP/1.1\r\n" + host + std::string("X-Nul: a\0b\r\n\r\n", 14), "400",
                "a NUL byte");
  expect_status("GET /healthz HTTP/1.1\r\n" + host + "Host: evil.example\r\n\r\n", "400", "two Host headers");
  EXPECT_EQ(http_get(port(), "/healthz").result(), http::status::ok);
}

TEST(ServerLifecycle, StopsCleanlyOnSigterm) {
  ServerProcess server;
  EXPECT_EQ(http_get(server.port(), "/healthz").result(), http::status::ok);
  EXPECT_EQ(server.stop(), 0);
}

TEST(ServerLifecycle, PortInUseFailsWithAClearError) {
  ServerProcess first;
  const auto result = run_strata({"serve", "--bind", "127.0.0.1", "--port", std::to_string(first.port())});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("in use"), std::string::npos) << result.output;
}

TEST(ServerLifecycle, BadOptionsAreRefused) {
  const auto result = run_strata({"serve", "--port", "70000"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("--port"), std::string::npos) << result.output;
}

TEST(ServerLifecycle, PicksABuiltInWorldAndScanner) {
  ServerProcess server({"--world", "yard", "--scanner", "lidar"});
  const auto world = nlohmann::json::parse(http_get(server.port(), "/api/v1/sim/world").body());
  EXPECT_EQ(world["name"], "yard");
  EXPECT_EQ(server.stop(), 0);
}

TEST(ServerLifecycle, LoadsAWorldFile) {
  const auto path =
      std::filesystem::path(::testing::TempDir()) / ("world-" + std::to_string(::getpid()) + ".json");
  std::ofstream(path)
      << R"({"name": "mine", "shapes": [{"type": "box", "min": [-5, -5, -1], "max": [5, 5, 0]}]})";
  ServerProcess server({"--world", path.string()});
  const auto world = nlohmann::json::parse(http_get(server.port(), "/api/v1/sim/world").body());
  EXPECT_EQ(world["name"], "mine");
  EXPECT_EQ(world["boxes"].size(), 1u);
  std::filesystem::remove(path);
}

TEST(ServerLifecycle, BadWorldFileIsAClearError) {
  const auto path =
      std::filesystem::path(::testing::TempDir()) / ("bad-" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, -1]}]})";
  const auto result = run_strata({"serve", "--port", "0", "--world", path.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("shapes[0]"), std::string::npos) << result.output;
  const auto unknown = run_strata({"serve", "--port", "0", "--world", "atlantis"});
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.output.find("campus"), std::string::npos) << unknown.output;  // lists the built-ins
  std::filesystem::remove(path);
}

TEST(ServerLifecycle, HelpDescribesServe) {
  const auto result = run_strata({"serve", "--help"});
  EXPECT_EQ(result.exit_code, 0);
  for (const char* option : {"--port", "--bind", "--web-root", "--pose-rate", "--seed", "--time-scale"}) {
    EXPECT_NE(result.output.find(option), std::string::npos) << option;
  }
}

}  // namespace
}  // namespace strata::testing

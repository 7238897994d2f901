// The Host check against DNS rebinding, on the real server with real clients (proto/PROTOCOL.md "Who may do
// what"): a page whose name was re-pointed at the robot still names itself in the Host header.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

class HostCheck : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new ServerProcess({"--scanner", "none", "--allowed-hosts", "robot.example"});
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static inline ServerProcess* server_ = nullptr;
};

TEST_F(HostCheck, AddressesLocalhostAndListedNamesAreServed) {
  const std::string port_suffix = ":" + std::to_string(port());
  for (const std::string& host :
       std::vector<std::string>{"127.0.0.1", "127.0.0.1" + port_suffix, "[::1]" + port_suffix, "localhost",
                                "LocalHost" + port_suffix, "robot.example", "Robot.Example" + port_suffix}) {
    EXPECT_EQ(http_get_for_host(port(), "/api/v1/pose", host).result(), http::status::ok) << host;
  }
  WsClient client(port());  // its Host header is 127.0.0.1:port
  EXPECT_EQ(client.read()["op"], "hello");
}

TEST_F(HostCheck, AnotherNameIsRefusedOnRestFilesAndTheWebSocket) {
  const std::string evil = "evil.example:" + std::to_string(port());
  for (const std::string target : {"/api/v1/pose", "/", "/metrics"}) {
    const auto refused = http_get_for_host(port(), target, evil);
    EXPECT_EQ(refused.result(), http::status::forbidden) << target;
    const auto body = nlohmann::json::parse(refused.body());
    expect_schema("rest", "error", body);
    EXPECT_EQ(body["error"]["code"], "forbidden");
  }
  // A name that only starts like an allowed one, and a malformed address, are other names.
  EXPECT_EQ(http_get_for_host(port(), "/api/v1/pose", "robot.example.evil").result(),
            http::status::forbidden);
  EXPECT_EQ(http_get_for_host(port(), "/api/v1/pose", "[::1").result(), http::status::forbidden);
  const auto upgrade = websocket_upgrade(port(), {{http::field::host, evil}});
  EXPECT_EQ(upgrade.result(), http::status::forbidden);
  EXPECT_EQ(nlohmann::json::parse(upgrade.body())["error"]["code"], "forbidden");
  const auto metrics = http_get(port(), "/metrics").body();
  EXPECT_EQ(metrics.find("strata_http_refused_host_total 0\n"), std::string::npos) << metrics;
}

TEST(HostOption, AStarAllowsAnyNameAndAMalformedNameIsRefusedAtStart) {
  ServerProcess server({"--scanner", "none", "--allowed-hosts", "*"});
  EXPECT_EQ(http_get_for_host(server.port(), "/api/v1/pose", "evil.example").result(), http::status::ok);
  const auto result = run_strata({"serve", "--port", "0", "--allowed-hosts", "http://robot.example"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("robot.example"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace strata::testing

// Faults of the sensor (issue #10): the simulated sensor stops delivering scans for a while (the fault
// drill `strata serve --sim-sensor-outage START,DURATION`); the status must say it stalled, then that it
// recovered, and the mapping must go on. The real server process and a real WebSocket client.
#include <gtest/gtest.h>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

TEST(SensorFault, TheStatusReportsAStalledSensorAndItsRecoveryAndMappingGoesOn) {
  // The yard, four times real time: the first scans come within seconds of simulated time, the outage
  // from t = 10 s to 30 s swallows the ones in between, and a stalled sensor is one that owes a scan for
  // more than 2 s of wall time.
  ServerProcess server({"--world", "yard", "--scanner", "tilting", "--time-scale", "4", "--sensor-timeout",
                        "2", "--sim-sensor-outage", "10,20"});
  WsClient client(server.port());
  const auto scans_of = [](const nlohmann::json& status) {
    return status["sensor"]["scans"].get<std::size_t>();
  };

  const auto before = wait_for_status(client, [&](const nlohmann::json& status) {
    return scans_of(status) >= 1 && status["registration"]["scans"].get<std::size_t>() >= 1;
  });
  EXPECT_EQ(before["sensor"]["state"], "ok") << before.dump();
  EXPECT_EQ(before["sensor"]["timeout_seconds"], 2.0);

  const auto stalled = wait_for_status(
      client, [](const nlohmann::json& status) { return status["sensor"]["state"] == "stalled"; });
  EXPECT_GT(stalled["sensor"]["overdue_seconds"].get<double>(), 2.0) << stalled.dump();
  EXPECT_GT(stalled["sensor"]["seconds_since_last_scan"].get<double>(), 2.0) << stalled.dump();
  const std::size_t scans_at_stall = scans_of(stalled);
  const auto registered_at_stall = stalled["registration"]["scans"].get<std::size_t>();
  const auto map_at_stall = stalled["map"]["version"].get<std::uint64_t>();
  // REST says the same thing in the same shape.
  expect_schema("rest", "status", nlohmann::json::parse(http_get(server.port(), "/api/v1/status").body()));

  const auto recovered =
      wait_for_status(client, [](const nlohmann::json& status) { return status["sensor"]["state"] == "ok"; });
  EXPECT_GT(scans_of(recovered), scans_at_stall) << "recovered without a new scan: " << recovered.dump();
  EXPECT_LT(recovered["sensor"]["overdue_seconds"].get<double>(), 2.0);

  // And the scans after the outage are registered and mapped. (Not asserted: the state at that moment. A
  // tilting scan owes its points for its whole sweep, which under ASan on a busy machine can itself take
  // longer than the 2 s timeout of wall time.)
  static_cast<void>(wait_for_status(client, [&](const nlohmann::json& status) {
    return status["registration"]["scans"].get<std::size_t>() > registered_at_stall &&
           status["map"]["version"].get<std::uint64_t>() > map_at_stall;
  }));
  EXPECT_EQ(server.stop(), 0);
}

TEST(SensorFault, AnOutageOptionThatMakesNoSenseIsRefused) {
  for (const char* outage : {"10", "x,5", "-1,5"}) {
    const auto result =
        run_strata({"serve", "--port", "0", "--bind", "127.0.0.1", "--sim-sensor-outage", outage});
    EXPECT_EQ(result.exit_code, 1) << outage << ": " << result.output;
    EXPECT_NE(result.output.find("--sim-sensor-outage"), std::string::npos) << result.output;
  }
}

}  // namespace
}  // namespace strata::testing

// The pose over a poor link (issue 59 items 2 and 3): the real server with its simulator, real WebSocket
// clients behind LinkProxy (40 ms each way, a rate, an outage).
//   steady: pose age (receipt - the pose's server_time, one clock) at 2 and 0.2 Mbit/s, after the
//           joining snapshot, while the map grows;
//   late joiner: at 0.5 Mbit/s, the gaps between poses while its map snapshot streams, and when the first
//           pose came;
//   outage: at 2 Mbit/s, the link down 3 s: how many poses older than 1 s arrive after it returns.
// Usage: strata_link_bench [seconds=20] [--warmup S (default 45)] [--smoke] [extra strata serve options...]
//   --smoke: the fixed waits (the late joiner's 30 s read, the outage's 8 s lead, 3 s down, 3 s after) cut
//            to a few seconds: CI's check that the bench still runs, not figures.
// Set STRATA_SERVER_BINARY to measure another build. Prints one JSON object.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench/percentile.hpp"
#include "integration/clients.hpp"
#include "integration/link_proxy.hpp"
#include "integration/server_process.hpp"

using strata::bench::percentile;

namespace {

using namespace std::chrono_literals;
using strata::testing::LinkConditions;
using strata::testing::LinkProxy;
using strata::testing::WsClient;

constexpr double kMbit = 1e6 / 8.0;  // bytes per second

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

nlohmann::json summary(const std::vector<double>& values_s) {
  return {{"samples", values_s.size()},
          {"p50_s", percentile(values_s, 0.5)},
          {"p99_s", percentile(values_s, 0.99)},
          {"max_s", percentile(values_s, 1.0)}};
}

/// What one client read: each pose's receipt and age, each tile frame's receipt.
struct Reading {
  std::vector<double> pose_received;  // wall clock, s
  std::vector<double> pose_age;       // s
  std::vector<double> tile_received;
  std::size_t snapshot_tiles = 0;  // the map's tiles in the first status it got
  std::size_t bytes = 0;
};

Reading read_for(WsClient& client, std::chrono::duration<double> span) {
  Reading reading;
  const auto until = std::chrono::steady_clock::now() + span;
  while (std::chrono::steady_clock::now() < until) {
    WsClient::Frame frame;
    try {
      frame = client.read_frame(5s);
    } catch (const strata::testing::Timeout&) {
      continue;
    }
    const double received = now_seconds();
    reading.bytes += frame.data.size();
    if (frame.binary) {
      if (!frame.data.empty() && frame.data[0] == 1)
        reading.tile_received.push_back(received);
      continue;
    }
    const auto message = nlohmann::json::parse(frame.data, nullptr, false);
    const std::string op = message.is_object() ? message.value("op", "") : "";
    if (op == "pose") {
      reading.pose_received.push_back(received);
      reading.pose_age.push_back(received - message["server_time"].get<double>());
    } else if (op == "status" && reading.snapshot_tiles == 0) {
      reading.snapshot_tiles = message["map"]["tiles"].get<std::size_t>();
    }
  }
  return reading;
}

nlohmann::json steady(std::uint16_t port, double mbit, double seconds) {
  LinkProxy link(port, LinkConditions{.delay = 40ms, .bytes_per_second = mbit * kMbit});
  WsClient client(link.port());
  const Reading reading = read_for(client, std::chrono::duration<double>(seconds));
  // The joining snapshot is the late-joiner case: count from the first pose after the last of its tiles.
  const double settled = reading.tile_received.size() >= reading.snapshot_tiles && reading.snapshot_tiles > 0
                             ? reading.tile_received[reading.snapshot_tiles - 1]
                             : 0.0;
  std::vector<double> ages;
  for (std::size_t i = 0; i < reading.pose_received.size(); ++i) {
    if (reading.pose_received[i] > settled)
      ages.push_back(reading.pose_age[i]);
  }
  nlohmann::json result = summary(ages);
  result["mbit_per_s"] = mbit;
  result["poses_per_s"] = static_cast<double>(ages.size()) / seconds;
  result["kbytes_per_s"] = static_cast<double>(reading.bytes) / seconds / 1e3;
  return result;
}

/// The fixed waits of the late-joiner and outage runs.
struct Waits {
  std::chrono::duration<double> late_joiner_read{30.0};
  std::chrono::duration<double> outage_lead{8.0};  // past the joining snapshot
  std::chrono::duration<double> outage{3.0};
  std::chrono::duration<double> after_outage{3.0};
};

nlohmann::json late_joiner(std::uint16_t port, double mbit, const Waits& waits) {
  LinkProxy link(port, LinkConditions{.delay = 40ms, .bytes_per_second = mbit * kMbit});
  const double connected = now_seconds();
  WsClient client(link.port());
  const Reading reading = read_for(client, waits.late_joiner_read);
  // The snapshot's last tile; a snapshot not whole in the read: the read's end (none at all: no map yet).
  double snapshot_end = connected;
  if (reading.snapshot_tiles > 0 && reading.tile_received.size() >= reading.snapshot_tiles)
    snapshot_end = reading.tile_received[reading.snapshot_tiles - 1];
  else if (!reading.tile_received.empty())
    snapshot_end = reading.tile_received.back();
  std::vector<double> gaps;
  std::size_t poses_during = 0;
  for (std::size_t i = 1; i < reading.pose_received.size() && reading.pose_received[i - 1] < snapshot_end;
       ++i) {
    gaps.push_back(reading.pose_received[i] - reading.pose_received[i - 1]);
    ++poses_during;
  }
  nlohmann::json result{
      {"mbit_per_s", mbit},
      {"snapshot_tiles", reading.snapshot_tiles},
      {"snapshot_s", snapshot_end - connected},
      {"first_pose_s", reading.pose_received.empty() ? -1.0 : reading.pose_received.front() - connected},
      {"poses_while_the_map_streams", poses_during},
      {"pose_gap", summary(gaps)}};
  return result;
}

nlohmann::json outage(std::uint16_t port, double mbit, const Waits& waits) {
  LinkProxy link(port, LinkConditions{.delay = 40ms, .bytes_per_second = mbit * kMbit});
  WsClient client(link.port());
  read_for(client, waits.outage_lead);
  link.set_down(true);
  std::this_thread::sleep_for(waits.outage);
  link.set_down(false);
  const Reading after = read_for(client, waits.after_outage);
  std::size_t stale = 0;
  for (const double age : after.pose_age)
    stale += age > 1.0 ? 1 : 0;
  return {{"mbit_per_s", mbit},
          {"outage_s", waits.outage.count()},
          {"poses_older_than_1s_after_it", stale},
          {"poses_after_it", after.pose_age.size()},
          {"age_after_it", summary(after.pose_age)}};
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::stod(argv[1]) : 20.0;
  double warmup_s = 45.0;  // a map to stream: ~225 s of the simulated drive
  std::vector<std::string> extra{"--time-scale", "5"};
  Waits waits;
  for (int i = 2; i < argc; ++i) {
    if (std::string(argv[i]) == "--warmup" && i + 1 < argc)
      warmup_s = std::stod(argv[++i]);
    else if (std::string(argv[i]) == "--smoke")
      waits = Waits{.late_joiner_read = 3s, .outage_lead = 2s, .outage = 1s, .after_outage = 1s};
    else
      extra.emplace_back(argv[i]);
  }
  strata::testing::ServerProcess server(extra);
  std::this_thread::sleep_for(std::chrono::duration<double>(warmup_s));
  nlohmann::json result;
  result["late_joiner"] = late_joiner(server.port(), 0.5, waits);
  result["steady_2mbit"] = steady(server.port(), 2.0, seconds);
  result["steady_0.2mbit"] = steady(server.port(), 0.2, seconds);
  result["outage"] = outage(server.port(), 2.0, waits);
  std::printf("%s\n", result.dump(2).c_str());
  // A bench whose server did not end cleanly measured a server that was failing.
  return server.stop() == 0 ? 0 : 1;
}

// Streaming latency over loopback (issue #7 targets): the real server process, N real WebSocket clients.
//   pose latency: pose `server_time` (when the server encoded it) to receipt, with N clients (target p99 <=
//   20 ms with 50 clients); scan-to-client latency: a tile frame's `stamp` (when the scan was taken) to
//   receipt (target p95 <= 150 ms).
// Usage: strata_stream_latency_bench [clients=50] [seconds=20] [extra strata serve options...]
// Prints one JSON object.
#include <algorithm>
#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench/percentile.hpp"
#include "integration/server_process.hpp"

using strata::bench::percentile;

namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

struct Samples {
  std::mutex mutex;
  std::vector<double> pose_ms;
  std::vector<double> tile_ms;
  std::size_t tile_bytes = 0;
  std::size_t tiles = 0;
};

void run_client(std::uint16_t port, std::atomic<bool>& stop, Samples& samples) {
  boost::asio::io_context io;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect({boost::asio::ip::make_address("127.0.0.1"), port});
  ws.set_option(websocket::stream_base::decorator([](websocket::request_type& request) {
    request.set(beast::http::field::sec_websocket_protocol, "strata.v1");
  }));
  ws.handshake("127.0.0.1", "/ws");
  std::vector<double> pose_ms;
  std::vector<double> tile_ms;
  std::size_t tile_bytes = 0;
  std::size_t tiles = 0;
  bool late_joiner_done = false;  // the first tiles are the late joiner's state, not fresh scans
  beast::flat_buffer buffer;
  while (!stop.load()) {
    buffer.clear();
    beast::error_code error;
    ws.read(buffer, error);
    if (error)
      break;
    const double received = now_seconds();
    const std::string data = beast::buffers_to_string(buffer.data());
    if (ws.got_binary()) {
      if (data.size() >= 40 && data[0] == 1) {
        double stamp = 0.0;
        std::memcpy(&stamp, data.data() + 16, sizeof stamp);
        ++tiles;
        tile_bytes += data.size();
        if (late_joiner_done && stamp > 0.0)
          tile_ms.push_back((received - stamp) * 1e3);
      }
      continue;
    }
    const auto message = nlohmann::json::parse(data, nullptr, false);
    if (message.is_object() && message.value("op", "") == "pose" && message.contains("server_time")) {
      late_joiner_done = true;
      pose_ms.push_back((received - message["server_time"].get<double>()) * 1e3);
    }
  }
  beast::error_code ignored;
  ws.next_layer().close(ignored);
  std::lock_guard lock(samples.mutex);
  samples.pose_ms.insert(samples.pose_ms.end(), pose_ms.begin(), pose_ms.end());
  samples.tile_ms.insert(samples.tile_ms.end(), tile_ms.begin(), tile_ms.end());
  samples.tile_bytes += tile_bytes;
  samples.tiles += tiles;
}

}  // namespace

int main(int argc, char** argv) {
  const int clients = argc > 1 ? std::stoi(argv[1]) : 50;
  const int seconds = argc > 2 ? std::stoi(argv[2]) : 20;
  std::vector<std::string> extra;
  for (int i = 3; i < argc; ++i)
    extra.emplace_back(argv[i]);
  strata::testing::ServerProcess server(extra);
  Samples samples;
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i)
    threads.emplace_back([&] { run_client(server.port(), stop, samples); });
  std::this_thread::sleep_for(std::chrono::seconds(seconds));
  stop = true;
  const int server_status = server.stop();  // unblocks the readers
  for (auto& thread : threads)
    thread.join();

  nlohmann::json result{{"clients", clients},
                        {"seconds", seconds},
                        {"pose",
                         {{"samples", samples.pose_ms.size()},
                          {"p50_ms", percentile(samples.pose_ms, 0.50)},
                          {"p99_ms", percentile(samples.pose_ms, 0.99)},
                          {"max_ms", percentile(samples.pose_ms, 1.0)}}},
                        {"scan_to_tile",
                         {{"samples", samples.tile_ms.size()},
                          {"p50_ms", percentile(samples.tile_ms, 0.50)},
                          {"p95_ms", percentile(samples.tile_ms, 0.95)},
                          {"p99_ms", percentile(samples.tile_ms, 0.99)},
                          {"max_ms", percentile(samples.tile_ms, 1.0)},
                          {"tiles_received", samples.tiles},
                          {"tile_bytes_received", samples.tile_bytes}}}};
  std::printf("%s\n", result.dump(2).c_str());
  // A bench whose server did not end cleanly measured a server that was failing.
  return server_status == 0 ? 0 : 1;
}

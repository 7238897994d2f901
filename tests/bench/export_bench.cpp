// Anonymous map exports against the server's responsiveness (issue 59 item 10): the real server with its
// simulator builds a map for a while, then N clients download it as PLY in a loop while one polls
// /healthz every 50 ms. Prints /healthz latency (p50, p99, max), and what the downloads got: answered,
// refused as busy (503), made or reused (X-Strata-Export), bytes.
// Usage: strata_export_bench [clients=8] [seconds=20] [warm-up seconds=60]
// Set STRATA_SERVER_BINARY to measure another build. Prints one JSON object.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench/percentile.hpp"
#include "integration/clients.hpp"
#include "integration/server_process.hpp"

using strata::bench::percentile;

int main(int argc, char** argv) {
  using namespace std::chrono_literals;
  using Clock = std::chrono::steady_clock;
  const int clients = argc > 1 ? std::stoi(argv[1]) : 8;
  const double seconds = argc > 2 ? std::stod(argv[2]) : 20.0;
  const double warm_up = argc > 3 ? std::stod(argv[3]) : 60.0;
  strata::testing::ServerProcess server({"--time-scale", "5"});
  std::this_thread::sleep_for(std::chrono::duration<double>(warm_up));

  std::atomic<bool> stop{false};
  std::atomic<long> answered{0}, busy{0}, failed{0}, made{0}, reused{0}, bytes{0};
  std::vector<std::thread> downloaders;
  for (int i = 0; i < clients; ++i) {
    downloaders.emplace_back([&] {
      while (!stop.load()) {
        try {
          const auto response = strata::testing::http_get(server.port(), "/api/v1/map?format=ply");
          if (response.result_int() == 200) {
            ++answered;
            bytes += static_cast<long>(response.body().size());
            (response["X-Strata-Export"] == "reused" ? reused : made)++;
          } else if (response.result_int() == 503) {
            ++busy;
            std::this_thread::sleep_for(200ms);  // a polite client backs off
          } else {
            ++failed;
          }
        } catch (const std::exception&) {
          ++failed;
        }
      }
    });
  }
  std::vector<double> health_ms;
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    const auto started = Clock::now();
    const auto response = strata::testing::http_get(server.port(), "/healthz");
    if (response.result_int() == 200)
      health_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - started).count());
    std::this_thread::sleep_for(50ms);
  }
  stop = true;
  for (auto& downloader : downloaders)
    downloader.join();
  const nlohmann::json result{{"clients", clients},
                              {"seconds", seconds},
                              {"healthz_ms",
                               {{"samples", health_ms.size()},
                                {"p50", percentile(health_ms, 0.5)},
                                {"p99", percentile(health_ms, 0.99)},
                                {"max", percentile(health_ms, 1.0)}}},
                              {"downloads",
                               {{"answered", answered.load()},
                                {"busy_503", busy.load()},
                                {"failed", failed.load()},
                                {"made", made.load()},
                                {"reused", reused.load()},
                                {"mean_bytes", answered.load() > 0 ? bytes.load() / answered.load() : 0}}}};
  std::printf("%s\n", result.dump(2).c_str());
  // A bench whose server did not end cleanly measured a server that was failing.
  return server.stop() == 0 ? 0 : 1;
}

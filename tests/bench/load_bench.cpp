// strata_load_bench: load and isolation (issue #10). Starts the real `strata serve` (simulated robot) on
// loopback, then for a bounded time holds N WebSocket clients, K of which stall (they complete the upgrade
// and never read again), plus a few REST pollers, and measures what the healthy clients get:
//   clients    healthy clients open (client side) and WebSocket clients the server holds (status stream)
//   pose       latency of pose frames: the frame's `server_time` (wall clock when the server encoded it)
//              to receipt, healthy clients only, after the warm-up (client-side queueing included: all
//              clients share two threads)
//   memory     the server's RSS (/proc/PID/status VmRSS) every few seconds: first, last, min, max, drift
//   mapping    scans mapped per minute (the map's version counts the scans inserted; from the status
//              stream), scans registered per minute, and how fast the simulated clock ran (pose stamp over
//              wall time)
//   rest       REST request latency and errors; stalled clients: whether the server dropped them
// First an unloaded baseline (one client, the monitor) of the same length unless --baseline-seconds says
// otherwise (0: none), then the loaded run, each with a fresh server. Prints one JSON line per sample and a
// JSON summary at the end. Not a test: it never fails on the numbers.
//
//   strata_load_bench [--clients N] [--stalled K] [--rest R] [--seconds S] [--baseline-seconds B]
//                     [--warmup W] [--sample-seconds P] [--time-scale X] [-- extra strata serve options]
//   defaults: 200 clients, 10 stalled, 4 REST pollers, 600 s, baseline as long, 15 s warm-up, 5 s samples,
//   time scale 1
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "bench/percentile.hpp"
#include "integration/server_process.hpp"

using strata::bench::percentile;

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct Options {
  int clients = 200;
  int stalled = 10;
  int rest = 4;
  double seconds = 600.0;
  std::optional<double> baseline_seconds;  // default: as long as the loaded run
  double warmup = 15.0;
  double sample_seconds = 5.0;
  double time_scale = 1.0;
  std::vector<std::string> serve_args;
};

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") {
      for (++i; i < argc; ++i)
        options.serve_args.emplace_back(argv[i]);
      break;
    }
    if (i + 1 >= argc)
      throw std::runtime_error("missing value after " + arg);
    const std::string value = argv[++i];
    if (arg == "--clients")
      options.clients = std::stoi(value);
    else if (arg == "--stalled")
      options.stalled = std::stoi(value);
    else if (arg == "--rest")
      options.rest = std::stoi(value);
    else if (arg == "--seconds")
      options.seconds = std::stod(value);
    else if (arg == "--baseline-seconds")
      options.baseline_seconds = std::stod(value);
    else if (arg == "--warmup")
      options.warmup = std::stod(value);
    else if (arg == "--sample-seconds")
      options.sample_seconds = std::stod(value);
    else if (arg == "--time-scale")
      options.time_scale = std::stod(value);
    else
      throw std::runtime_error("unknown option " + arg);
  }
  if (options.clients < 1 || options.stalled < 0 || options.stalled >= options.clients || options.rest < 0 ||
      !(options.seconds > 0.0) || !(options.sample_seconds > 0.0) || !(options.time_scale > 0.0))
    throw std::runtime_error("need clients >= 1, 0 <= stalled < clients, rest >= 0, seconds > 0");
  return options;
}

double wall_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

json latency_summary(const std::vector<double>& ms) {
  return {{"samples", ms.size()},
          {"p50_ms", percentile(ms, 0.50)},
          {"p95_ms", percentile(ms, 0.95)},
          {"p99_ms", percentile(ms, 0.99)},
          {"max_ms", percentile(ms, 1.0)}};
}

/// One status message as the monitor client saw it.
struct StatusSample {
  double t = 0.0;  // s since the run started
  std::size_t server_clients = 0;
  std::size_t scans = 0;
  std::size_t rejected = 0;
  std::size_t dropped = 0;
  std::uint64_t map_version = 0;
  std::uint64_t map_bytes = 0;
  std::string sensor;  // the status's sensor state, when the server reports one
};

/// What every client and poller records; the handlers of two threads write, the sampler reads.
class Measurements {
 public:
  explicit Measurements(Clock::time_point start, double warmup) : start_(start), warmup_(warmup) {}

  [[nodiscard]] double elapsed() const {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }
  [[nodiscard]] bool warmed_up() const { return elapsed() >= warmup_; }

  void pose_latency(double ms) {
    if (!warmed_up())
      return;
    std::lock_guard lock(mutex_);
    pose_ms_.push_back(ms);
    interval_pose_ms_.push_back(ms);
  }
  void rest_latency(double ms) {
    std::lock_guard lock(mutex_);
    rest_ms_.push_back(ms);
  }
  void status(StatusSample sample) {
    std::lock_guard lock(mutex_);
    status_.push_back(std::move(sample));
  }
  void robot_time(double stamp) {
    std::lock_guard lock(mutex_);
    robot_times_.emplace_back(elapsed(), stamp);
  }
  void error(const std::string& what) {
    std::lock_guard lock(mutex_);
    ++errors_[what];
  }

  std::vector<double> take_interval_pose() {
    std::lock_guard lock(mutex_);
    return std::exchange(interval_pose_ms_, {});
  }
  [[nodiscard]] std::optional<StatusSample> last_status() const {
    std::lock_guard lock(mutex_);
    if (status_.empty())
      return std::nullopt;
    return status_.back();
  }
  [[nodiscard]] std::vector<double> pose_ms() const {
    std::lock_guard lock(mutex_);
    return pose_ms_;
  }
  [[nodiscard]] std::vector<double> rest_ms() const {
    std::lock_guard lock(mutex_);
    return rest_ms_;
  }
  [[nodiscard]] std::vector<StatusSample> statuses() const {
    std::lock_guard lock(mutex_);
    return status_;
  }
  [[nodiscard]] std::vector<std::pair<double, double>> robot_times() const {
    std::lock_guard lock(mutex_);
    return robot_times_;
  }
  [[nodiscard]] std::map<std::string, int> errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
  }

  std::atomic<int> healthy_open{0};
  std::atomic<int> stalled_open{0};  // upgraded; from then on the client side cannot tell
  std::atomic<long> rest_requests{0};
  std::atomic<long> rest_failures{0};

 private:
  Clock::time_point start_;
  double warmup_;
  mutable std::mutex mutex_;
  std::vector<double> pose_ms_;
  std::vector<double> interval_pose_ms_;
  std::vector<double> rest_ms_;
  std::vector<StatusSample> status_;
  std::vector<std::pair<double, double>> robot_times_;  // (elapsed, pose stamp), monitor only
  std::map<std::string, int> errors_;
};

/// The number after `"key":` in compact JSON (what the server sends), without parsing the whole message:
/// 200 clients at 25 Hz.
std::optional<double> number_after(std::string_view text, std::string_view key) {
  const std::size_t at = text.find(key);
  if (at == std::string_view::npos)
    return std::nullopt;
  const std::string tail(text.substr(at + key.size(), 32));
  char* end = nullptr;
  const double value = std::strtod(tail.c_str(), &end);
  if (end == tail.c_str())
    return std::nullopt;
  return value;
}

enum class ClientKind { kHealthy, kMonitor, kStalled };

/// One WebSocket client on /ws. Healthy clients read everything; the monitor also records the status
/// stream; a stalled client completes the upgrade and then never reads again.
class LoadClient : public std::enable_shared_from_this<LoadClient> {
 public:
  LoadClient(asio::io_context& io, std::uint16_t port, ClientKind kind, Measurements& measurements)
      : ws_(asio::make_strand(io)), port_(port), kind_(kind), m_(measurements) {}

  void start() {
    beast::get_lowest_layer(ws_).expires_after(std::chrono::seconds(30));
    beast::get_lowest_layer(ws_).async_connect(
        tcp::endpoint(asio::ip::make_address("127.0.0.1"), port_),
        [self = shared_from_this()](beast::error_code error) { self->on_connect(error); });
  }

  /// Ends the client from any thread.
  void close() {
    asio::post(ws_.get_executor(), [self = shared_from_this()] {
      self->closing_ = true;
      beast::error_code ignored;
      beast::get_lowest_layer(self->ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
      beast::get_lowest_layer(self->ws_).close();
    });
  }

  [[nodiscard]] ClientKind kind() const { return kind_; }
  [[nodiscard]] bool upgraded() const { return upgraded_; }
  [[nodiscard]] long poses() const { return poses_; }
  /// For a stalled client, after the io threads stopped: whether the server has closed the connection
  /// (reads what the socket holds, up to `budget`, and looks for the end of the stream).
  [[nodiscard]] std::string fate(std::chrono::milliseconds budget) {
    auto& socket = beast::get_lowest_layer(ws_).socket();
    if (!socket.is_open())
      return "never_connected";
    const int fd = socket.native_handle();
    const auto deadline = Clock::now() + budget;
    std::vector<char> buffer(1 << 16);
    while (Clock::now() < deadline) {
      pollfd pfd{fd, POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (poll(&pfd, 1, static_cast<int>(std::max<long>(1, left.count()))) <= 0)
        return "open";  // nothing more arrives: the server still holds it (or is still sending)
      const ssize_t n = recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
      if (n == 0)
        return "closed_by_server";
      if (n < 0)
        return errno == EAGAIN ? "open" : "reset_by_server";
    }
    return "open";
  }

 private:
  void on_connect(beast::error_code error) {
    if (error)
      return fail("connect", error);
    beast::get_lowest_layer(ws_).expires_never();
    ws_.set_option(websocket::stream_base::decorator([](websocket::request_type& request) {
      request.set(http::field::sec_websocket_protocol, "strata.v1");
    }));
    ws_.async_handshake("127.0.0.1", "/ws",
                        [self = shared_from_this()](beast::error_code e) { self->on_handshake(e); });
  }

  void on_handshake(beast::error_code error) {
    if (error)
      return fail("handshake", error);
    upgraded_ = true;
    if (kind_ == ClientKind::kStalled) {
      ++m_.stalled_open;
      return;  // stops reading for good
    }
    ++m_.healthy_open;
    read();
  }

  void read() {
    buffer_.clear();
    ws_.async_read(
        buffer_, [self = shared_from_this()](beast::error_code error, std::size_t) { self->on_read(error); });
  }

  void on_read(beast::error_code error) {
    if (error) {
      --m_.healthy_open;
      if (!closing_)
        fail("read", error);
      return;
    }
    const double received = wall_now();
    if (ws_.got_text()) {
      const auto data = buffer_.cdata();
      const std::string_view text(static_cast<const char*>(data.data()), data.size());
      if (text.find("\"op\":\"pose\"") != std::string_view::npos) {
        ++poses_;
        if (const auto sent = number_after(text, "\"server_time\":"))
          m_.pose_latency((received - *sent) * 1e3);
        if (kind_ == ClientKind::kMonitor) {
          if (const auto stamp = number_after(text, "\"stamp\":"))
            m_.robot_time(*stamp);
        }
      } else if (kind_ == ClientKind::kMonitor && text.find("\"op\":\"status\"") != std::string_view::npos) {
        record_status(text);
      }
    }
    read();
  }

  void record_status(std::string_view text) {
    const json status = json::parse(text, nullptr, false);
    if (!status.is_object())
      return m_.error("monitor: status is not JSON");
    StatusSample sample;
    sample.t = m_.elapsed();
    sample.server_clients = status.value("clients", 0U);
    const json& registration = status["registration"];
    sample.scans = registration.value("scans", 0U);
    sample.rejected = registration.value("rejected", 0U);
    sample.dropped = registration.value("dropped", 0U);
    sample.map_version = status["map"].value("version", std::uint64_t{0});
    sample.map_bytes = status["map"].value("bytes", std::uint64_t{0});
    if (status.contains("sensor"))
      sample.sensor = status["sensor"].value("state", "");
    m_.status(std::move(sample));
  }

  void fail(const char* step, beast::error_code error) {
    if (closing_)
      return;
    m_.error(std::string(kind_ == ClientKind::kStalled ? "stalled " : "ws ") + step + ": " + error.message());
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  std::uint16_t port_;
  ClientKind kind_;
  Measurements& m_;
  bool upgraded_ = false;
  bool closing_ = false;
  long poses_ = 0;
};

/// A script polling REST: one GET after another on fresh connections, `period` apart, round the targets.
class RestPoller : public std::enable_shared_from_this<RestPoller> {
 public:
  RestPoller(asio::io_context& io, std::uint16_t port, std::chrono::milliseconds period, int offset,
             Measurements& measurements)
      : strand_(asio::make_strand(io)),
        timer_(strand_),
        port_(port),
        period_(period),
        next_(offset),
        m_(measurements) {}

  void start() { request(); }
  void stop() {
    asio::post(strand_, [self = shared_from_this()] {
      self->stopping_ = true;
      self->timer_.cancel();
      if (self->stream_)
        self->stream_->close();
    });
  }

 private:
  static constexpr std::array<const char*, 4> kTargets{"/api/v1/status", "/api/v1/pose", "/api/v1/goal",
                                                       "/api/v1/path"};

  void request() {
    if (stopping_)
      return;
    stream_.emplace(strand_);
    stream_->expires_after(std::chrono::seconds(10));
    request_ = {http::verb::get, kTargets[static_cast<std::size_t>(next_++) % kTargets.size()], 11};
    request_.set(http::field::host, "127.0.0.1");
    response_ = {};
    buffer_.clear();
    started_ = Clock::now();
    stream_->async_connect(
        tcp::endpoint(asio::ip::make_address("127.0.0.1"), port_),
        [self = shared_from_this()](beast::error_code error) {
          if (error)
            return self->done(error);
          http::async_write(*self->stream_, self->request_, [self](beast::error_code e, std::size_t) {
            if (e)
              return self->done(e);
            http::async_read(*self->stream_, self->buffer_, self->response_,
                             [self](beast::error_code r, std::size_t) { self->done(r); });
          });
        });
  }

  void done(beast::error_code error) {
    if (stopping_)
      return;
    ++m_.rest_requests;
    if (error) {
      ++m_.rest_failures;
      m_.error("rest: " + error.message());
    } else if (response_.result() != http::status::ok) {
      ++m_.rest_failures;
      m_.error("rest: HTTP " + std::to_string(response_.result_int()) + " " + std::string(request_.target()));
    } else {
      m_.rest_latency(std::chrono::duration<double, std::milli>(Clock::now() - started_).count());
    }
    beast::error_code ignored;
    stream_->socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream_->close();
    timer_.expires_after(period_);
    timer_.async_wait([self = shared_from_this()](beast::error_code e) {
      if (!e)
        self->request();
    });
  }

  asio::strand<asio::io_context::executor_type> strand_;
  asio::steady_timer timer_;
  std::uint16_t port_;
  std::chrono::milliseconds period_;
  int next_;
  Measurements& m_;
  std::optional<beast::tcp_stream> stream_;
  http::request<http::empty_body> request_;
  http::response<http::string_body> response_;
  beast::flat_buffer buffer_;
  Clock::time_point started_;
  bool stopping_ = false;
};

/// GET `target` with its own io_context, bounded by `timeout`; the body, or nothing.
std::optional<std::string> fetch(std::uint16_t port, const std::string& target,
                                 std::chrono::seconds timeout) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.expires_after(timeout);
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, "127.0.0.1");
  http::response<http::string_body> response;
  beast::flat_buffer buffer;
  std::optional<std::string> body;
  stream.async_connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), [&](beast::error_code e) {
    if (e)
      return;
    http::async_write(stream, request, [&](beast::error_code w, std::size_t) {
      if (w)
        return;
      http::async_read(stream, buffer, response, [&](beast::error_code r, std::size_t) {
        if (!r && response.result() == http::status::ok)
          body = response.body();
      });
    });
  });
  io.run();
  return body;
}

/// A counter from the Prometheus text of /metrics; -1 when absent.
long metric(const std::string& text, const std::string& name) {
  std::size_t at = 0;
  while ((at = text.find(name, at)) != std::string::npos) {
    const bool line_start = at == 0 || text[at - 1] == '\n';
    at += name.size();
    if (line_start && at < text.size() && text[at] == ' ')
      return std::atol(text.c_str() + at + 1);
  }
  return -1;
}

struct RssSample {
  double t = 0.0;
  long kib = 0;
};

json rss_summary(const std::vector<RssSample>& samples, double from) {
  std::vector<RssSample> kept;
  for (const auto& sample : samples) {
    if (sample.t >= from && sample.kib > 0)
      kept.push_back(sample);
  }
  if (kept.empty())
    return {{"samples", 0}};
  long min = kept.front().kib;
  long max = min;
  for (const auto& sample : kept) {
    min = std::min(min, sample.kib);
    max = std::max(max, sample.kib);
  }
  const double first = static_cast<double>(kept.front().kib);
  const double last = static_cast<double>(kept.back().kib);
  return {{"samples", kept.size()},
          {"from_s", from},
          {"first_kib", kept.front().kib},
          {"last_kib", kept.back().kib},
          {"min_kib", min},
          {"max_kib", max},
          {"drift_pct", (last - first) / first * 100.0},
          {"range_pct", static_cast<double>(max - min) / static_cast<double>(min) * 100.0}};
}

/// Scans mapped per minute (the map's version increments with every scan inserted) between the first status
/// at or after `from` and the last one; also registration and simulated-clock rates. (registration.rejected
/// also counts degenerate geometry that was corrected partly, and mapped: not a count of unmapped scans.)
json mapping_summary(const std::vector<StatusSample>& statuses,
                     const std::vector<std::pair<double, double>>& robot_times, double from) {
  const StatusSample* first = nullptr;
  for (const auto& sample : statuses) {
    if (sample.t >= from) {
      first = &sample;
      break;
    }
  }
  if (first == nullptr || statuses.empty() || statuses.back().t <= first->t)
    return {{"samples", 0}};
  const StatusSample& last = statuses.back();
  const double minutes = (last.t - first->t) / 60.0;
  const auto mapped = static_cast<double>(last.map_version - first->map_version);
  json result{{"from_s", first->t},
              {"to_s", last.t},
              {"scans_mapped", mapped},
              {"scans_mapped_per_min", mapped / minutes},
              {"scans_registered", last.scans - first->scans},
              {"scans_registered_per_min", static_cast<double>(last.scans - first->scans) / minutes},
              {"scans_dropped_by_localizer", last.dropped - first->dropped},
              {"registrations_rejected_or_partial", last.rejected - first->rejected},
              {"map_bytes_first", first->map_bytes},
              {"map_bytes_last", last.map_bytes}};
  // Simulated seconds per wall second: below the --time-scale, the simulator fell behind (CPU starved).
  std::optional<std::pair<double, double>> a;
  for (const auto& sample : robot_times) {
    if (sample.first >= from) {
      a = sample;
      break;
    }
  }
  if (a && !robot_times.empty() && robot_times.back().first > a->first) {
    result["sim_seconds_per_second"] =
        (robot_times.back().second - a->second) / (robot_times.back().first - a->first);
  }
  return result;
}

struct RunSpec {
  std::string phase;
  int clients = 1;  // WebSocket clients, the monitor included
  int stalled = 0;
  int rest = 0;
  double seconds = 0.0;
};

json run(const Options& options, const RunSpec& spec) {
  std::vector<std::string> serve_args{"--time-scale", std::to_string(options.time_scale)};
  serve_args.insert(serve_args.end(), options.serve_args.begin(), options.serve_args.end());
  strata::testing::ServerProcess server(serve_args);
  const auto start = Clock::now();
  Measurements m(start, options.warmup);

  asio::io_context io;
  auto work = asio::make_work_guard(io);
  std::vector<std::thread> threads;
  for (int i = 0; i < 2; ++i)
    threads.emplace_back([&io] { io.run(); });

  // The stalled clients spread evenly among the others; the monitor first. One connection every 10 ms.
  std::vector<std::shared_ptr<LoadClient>> clients;
  const int stride = spec.stalled > 0 ? spec.clients / spec.stalled : 0;
  int stalled = 0;
  for (int i = 0; i < spec.clients; ++i) {
    ClientKind kind = ClientKind::kHealthy;
    if (i == 0) {
      kind = ClientKind::kMonitor;
    } else if (stride > 0 && i % stride == stride / 2 && stalled < spec.stalled) {
      kind = ClientKind::kStalled;
      ++stalled;
    }
    clients.push_back(std::make_shared<LoadClient>(io, server.port(), kind, m));
  }
  std::vector<std::shared_ptr<RestPoller>> pollers;
  for (int i = 0; i < spec.rest; ++i) {
    pollers.push_back(std::make_shared<RestPoller>(io, server.port(), std::chrono::milliseconds(200), i, m));
    pollers.back()->start();
  }
  for (auto& client : clients) {
    client->start();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }

  std::vector<RssSample> rss;
  std::vector<json> lines;
  long slow_dropped = 0;
  double next_sample = 0.0;
  while (m.elapsed() < spec.seconds) {
    const double t = m.elapsed();
    if (t < next_sample) {
      std::this_thread::sleep_for(std::chrono::duration<double>(std::min(next_sample - t, 0.2)));
      continue;
    }
    next_sample += options.sample_seconds;
    const long kib = server.resident_kib();
    rss.push_back({t, kib});
    if (const auto metrics = fetch(server.port(), "/metrics", std::chrono::seconds(5)))
      slow_dropped = metric(*metrics, "strata_ws_slow_clients_dropped_total");
    else
      m.error("metrics: no answer in 5 s");
    const auto interval = m.take_interval_pose();
    const auto status = m.last_status();
    json line{{"phase", spec.phase},
              {"t", std::round(t * 10.0) / 10.0},
              {"healthy_open", m.healthy_open.load()},
              {"stalled_upgraded", m.stalled_open.load()},
              {"server_clients", status ? static_cast<long>(status->server_clients) : -1},
              {"slow_dropped", slow_dropped},
              {"rss_kib", kib},
              {"pose_interval", latency_summary(interval)},
              {"rest_requests", m.rest_requests.load()},
              {"rest_failures", m.rest_failures.load()}};
    if (status) {
      line["scans"] = status->scans;
      line["map_version"] = status->map_version;
      line["map_bytes"] = status->map_bytes;
      if (!status->sensor.empty())
        line["sensor"] = status->sensor;
    }
    std::printf("%s\n", line.dump().c_str());
    std::fflush(stdout);
    lines.push_back(std::move(line));
  }

  // Stop the clients, then look at what became of the stalled ones before the server goes.
  for (auto& poller : pollers)
    poller->stop();
  for (auto& client : clients) {
    if (client->kind() != ClientKind::kStalled)
      client->close();
  }
  // Every operation ends with its socket; the threads return when nothing is left (a stuck one: 5 s).
  work.reset();
  for (int i = 0; i < 50 && !io.stopped(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  io.stop();
  for (auto& thread : threads)
    thread.join();
  std::map<std::string, int> stalled_fates;
  for (auto& client : clients) {
    if (client->kind() == ClientKind::kStalled)
      ++stalled_fates[client->fate(std::chrono::milliseconds(500))];
  }
  long min_poses = -1;
  long max_poses = 0;
  for (const auto& client : clients) {
    if (client->kind() == ClientKind::kStalled)
      continue;
    min_poses = min_poses < 0 ? client->poses() : std::min(min_poses, client->poses());
    max_poses = std::max(max_poses, client->poses());
  }
  const int exit_status = server.stop();

  const auto statuses = m.statuses();
  std::size_t clients_min = 0;
  std::size_t clients_max = 0;
  std::optional<double> stalled_gone_at;  // when the server first held only the healthy clients
  for (const auto& s : statuses) {
    if (s.t < options.warmup)
      continue;
    clients_min = clients_min == 0 ? s.server_clients : std::min(clients_min, s.server_clients);
    clients_max = std::max(clients_max, s.server_clients);
  }
  for (const auto& s : statuses) {
    if (spec.stalled > 0 && s.t > 1.0 &&
        s.server_clients == static_cast<std::size_t>(spec.clients - spec.stalled)) {
      stalled_gone_at = s.t;
      break;
    }
  }
  json summary{{"phase", spec.phase},
               {"seconds", spec.seconds},
               {"time_scale", options.time_scale},
               {"ws_clients", spec.clients},
               {"stalled", spec.stalled},
               {"rest_pollers", spec.rest},
               {"warmup_s", options.warmup},
               {"clients",
                {{"server_held_min_after_warmup", clients_min},
                 {"server_held_max_after_warmup", clients_max},
                 {"server_held_last", statuses.empty() ? 0 : statuses.back().server_clients},
                 {"stalled_all_dropped_at_s", stalled_gone_at ? json(*stalled_gone_at) : json(nullptr)},
                 {"slow_dropped_metric", slow_dropped},
                 {"stalled_fates", stalled_fates},
                 {"healthy_poses_min", min_poses},
                 {"healthy_poses_max", max_poses}}},
               {"pose_latency_healthy", latency_summary(m.pose_ms())},
               {"rss", rss_summary(rss, options.warmup)},
               {"rss_all", rss_summary(rss, 0.0)},
               {"mapping", mapping_summary(statuses, m.robot_times(), options.warmup)},
               {"rest",
                {{"requests", m.rest_requests.load()},
                 {"failures", m.rest_failures.load()},
                 {"latency", latency_summary(m.rest_ms())}}},
               {"errors", m.errors()},
               {"server_exit_status", exit_status}};
  return summary;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  try {
    options = parse(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "strata_load_bench: %s\n", error.what());
    return 2;
  }
  json result;
  const double baseline_seconds = options.baseline_seconds.value_or(options.seconds);
  if (baseline_seconds > 0.0)
    result["baseline"] = run(options, {"baseline", 1, 0, 0, baseline_seconds});
  result["loaded"] =
      run(options, {"loaded", options.clients, options.stalled, options.rest, options.seconds});
  if (result.contains("baseline")) {
    const json& base = result["baseline"]["mapping"];
    const json& loaded = result["loaded"]["mapping"];
    if (base.contains("scans_mapped_per_min") && loaded.contains("scans_mapped_per_min") &&
        base["scans_mapped_per_min"].get<double>() > 0.0) {
      result["mapping_rate_change_pct"] =
          (loaded["scans_mapped_per_min"].get<double>() / base["scans_mapped_per_min"].get<double>() - 1.0) *
          100.0;
    }
  }
  std::printf("%s\n", result.dump(2).c_str());
  return 0;
}

// The limits on plain connections, on the real server with real sockets (proto/PROTOCOL.md "Limits"): the
// HTTP connection limit, and a server that runs out of file descriptors and recovers.
#include <gtest/gtest.h>
#include <signal.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

/// GET, tried again while the server still counts a connection that was just closed (it notices the close
/// asynchronously) and answers 503.
http::response<http::string_body> get_once_a_place_is_free(std::uint16_t port, const std::string& target) {
  auto response = http_get(port, target);
  for (int attempt = 0; attempt < 400 && response.result() == http::status::service_unavailable; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
    response = http_get(port, target);
  }
  return response;
}

/// A TCP connection that sends nothing: an idle keep-alive or a slow client.
std::unique_ptr<tcp::socket> idle_connection(boost::asio::io_context& io, std::uint16_t port) {
  auto socket = std::make_unique<tcp::socket>(io);
  socket->connect({boost::asio::ip::make_address("127.0.0.1"), port});
  return socket;
}

/// A TCP connection from `source` (any 127.x.y.z is this machine): another host, as the server sees it.
std::unique_ptr<tcp::socket> connection_from(boost::asio::io_context& io, const std::string& source,
                                             std::uint16_t port) {
  auto socket = std::make_unique<tcp::socket>(io);
  socket->open(tcp::v4());
  socket->bind({boost::asio::ip::make_address(source), 0});
  socket->connect({boost::asio::ip::make_address("127.0.0.1"), port});
  return socket;
}

/// GET `target` over `socket`; the response.
http::response<http::string_body> get_over(tcp::socket& socket, const std::string& target) {
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, "127.0.0.1");
  http::write(socket, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(socket, buffer, response);
  return response;
}

std::size_t lines_containing(const std::filesystem::path& file, const std::string& text) {
  std::ifstream in(file);
  std::size_t count = 0;
  for (std::string line; std::getline(in, line);)
    count += line.find(text) != std::string::npos ? 1 : 0;
  return count;
}

TEST(HttpConnectionLimit, OneConnectionOverTheLimitGets503UntilOneCloses) {
  ServerProcess server({"--scanner", "none", "--max-http-connections", "2"});
  // WebSocket clients give their HTTP place back once upgraded: these two leave both free.
  WsClient first(server.port());
  first.read_op("hello");
  WsClient second(server.port());
  second.read_op("hello");

  // The server accepts in order: once the third connection is accepted, these two hold both places.
  boost::asio::io_context io;
  auto idle = idle_connection(io, server.port());
  const auto other_idle = idle_connection(io, server.port());
  const auto refused = http_get(server.port(), "/healthz");
  EXPECT_EQ(refused.result(), http::status::service_unavailable);
  EXPECT_EQ(refused[http::field::retry_after], "10");
  const auto body = nlohmann::json::parse(refused.body());
  expect_schema("rest", "error", body);
  EXPECT_EQ(body["error"]["code"], "unavailable");
  EXPECT_NE(body["error"]["message"].get<std::string>().find("at most 2"), std::string::npos) << body;

  idle.reset();  // one place comes free once the server has noticed the close
  EXPECT_EQ(get_once_a_place_is_free(server.port(), "/healthz").result(), http::status::ok);
  const auto metrics = get_once_a_place_is_free(server.port(), "/metrics").body();
  EXPECT_EQ(metrics.find("strata_http_refused_full_total 0\n"), std::string::npos) << metrics;
  first.read_op("pose");  // the WebSocket clients were not disturbed
}

TEST(ConnectionLimits, OneHostCannotLockTheOthersOrTheOperatorOut) {
  ServerProcess server({"--scanner", "none", "--max-connections-per-address", "6", "--max-clients", "2"});
  // One host (127.0.0.2) opens its every place and one more: that one gets 503 saying why.
  boost::asio::io_context io;
  std::vector<std::unique_ptr<tcp::socket>> crowd;
  for (int i = 0; i < 6; ++i)
    crowd.push_back(connection_from(io, "127.0.0.2", server.port()));
  EXPECT_EQ(get_over(*crowd.front(), "/healthz").result(), http::status::ok);  // all six were accepted
  auto one_more = connection_from(io, "127.0.0.2", server.port());
  const auto refused = get_over(*one_more, "/healthz");
  EXPECT_EQ(refused.result(), http::status::service_unavailable);
  const auto body = nlohmann::json::parse(refused.body());
  expect_schema("rest", "error", body);
  EXPECT_NE(body["error"]["message"].get<std::string>().find("from your address"), std::string::npos) << body;
  // Other hosts are served.
  EXPECT_EQ(http_get(server.port(), "/healthz").result(), http::status::ok);

  // Viewers take every WebSocket place (max-clients 2): one more viewer is refused, the operator is not.
  WsClient first(server.port());
  first.read_op("hello");
  WsClient second(server.port());
  second.read_op("hello");
  EXPECT_EQ(websocket_upgrade(server.port(), {}).result(), http::status::service_unavailable);
  auto op = WsClient::operator_client(server.port(), kTestOperatorToken);
  EXPECT_EQ(op->read_op("hello")["role"], "operator");
  const auto metrics = http_get(server.port(), "/metrics").body();
  EXPECT_NE(metrics.find("strata_refused_address_total 1\n"), std::string::npos) << metrics;
  EXPECT_EQ(server.stop(), 0);
}

TEST(AcceptBackOff, AServerOutOfDescriptorsRecoversWithoutFloodingItsLog) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // The sanitizer runtimes need descriptors of their own: UBSan's vptr check probes memory through a pipe,
  // and without a free descriptor it reports any object as invalid and stops the server. Run in release.
  GTEST_SKIP() << "a server out of file descriptors cannot run under the sanitizers (they need descriptors)";
#endif
  const auto log =
      std::filesystem::temp_directory_path() / ("strata-accept-backoff-" + std::to_string(getpid()) + ".log");
  // 64 descriptors: the server's own files and a few dozen connections.
  ServerProcess server({"--scanner", "none"}, ProcessLimits{.open_files = 64, .log_file = log});
  boost::asio::io_context io;
  std::vector<std::unique_ptr<tcp::socket>> connections;
  // The kernel completes connections into the listen backlog whether or not the server can accept them.
  for (int i = 0; i < 100; ++i)
    connections.push_back(idle_connection(io, server.port()));
  bool ran_out = false;
  for (int attempt = 0; attempt < 400 && !ran_out; ++attempt) {
    ran_out = lines_containing(log, "accept failed") > 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  ASSERT_TRUE(ran_out) << "the server never ran out of descriptors";
  // Out of descriptors for a while: a server retrying at once would log thousands of lines by now.
  std::this_thread::sleep_for(std::chrono::seconds(1));
  connections.clear();

  EXPECT_EQ(get_once_a_place_is_free(server.port(), "/healthz").result(), http::status::ok);
  EXPECT_EQ(kill(server.pid(), 0), 0);  // still running
  // One line per 10 s at most (and the test takes a few seconds).
  EXPECT_LE(lines_containing(log, "accept failed"), 2U);
  EXPECT_GE(lines_containing(log, "accepting connections again"), 1U);
  std::filesystem::remove(log);
}

TEST(LogFlood, RefusedOriginsCannotFloodTheLog) {
  // Issue 59 item 7: each refused upgrade logged its whole Origin header, unthrottled: 80 MB in 2.5 s.
  const auto log =
      std::filesystem::temp_directory_path() / ("strata-log-flood-" + std::to_string(getpid()) + ".log");
  ServerProcess server({"--scanner", "none"}, ProcessLimits{.log_file = log});
  const std::string origin = "https://" + std::string(6000, 'e') + ".example";
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 200; ++i)
    ASSERT_EQ(websocket_upgrade(server.port(), {{http::field::origin, origin}}).result(),
              http::status::forbidden);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // a token for one more line at least
  ASSERT_EQ(websocket_upgrade(server.port(), {{http::field::origin, origin}}).result(),
            http::status::forbidden);
  // A burst of 10 and one line a second after: however slow the machine, far fewer than the refusals.
  const auto seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto most = static_cast<std::size_t>(10.0 + seconds + 1.0);
  EXPECT_EQ(server.stop(), 0);
  const std::size_t refused = lines_containing(log, "refused a WebSocket from the browser origin");
  EXPECT_GE(refused, 2U);
  EXPECT_LE(refused, most) << "201 refusals in " << seconds << " s";
  EXPECT_GE(lines_containing(log, "more like it not logged"), 1U);
  // Each line is cut to the Origin's first 80 bytes: the headers alone are 1.2 MB.
  EXPECT_LT(std::filesystem::file_size(log), 4000U + 300U * most);
  std::filesystem::remove(log);
}

}  // namespace
}  // namespace strata::testing

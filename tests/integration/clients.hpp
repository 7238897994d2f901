#pragma once

// Real clients for integration tests: an HTTP client and a WebSocket client over loopback TCP, plain or
// TLS (https://, wss://), all from Boost.Beast, talking to the strata process exactly as a user's script
// would. The TLS variants verify the server's certificate against one trusted certificate file.

#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "integration/protocol_schemas.hpp"

namespace strata::testing {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace ssl = boost::asio::ssl;
using tcp = boost::asio::ip::tcp;
using TlsSocket = ssl::stream<tcp::socket>;

struct Timeout : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The schemas of proto/, loaded once per test process.
inline ProtocolSchemas& protocol_schemas() {
  static ProtocolSchemas schemas;
  return schemas;
}

/// Adds a test failure when `value` does not match `proto/schemas/<group>/<name>.schema.json`.
inline void expect_schema(const std::string& group, const std::string& name, const nlohmann::json& value) {
  const std::string violations = protocol_schemas().violations(group, name, value);
  EXPECT_TRUE(violations.empty()) << group << "/" << name << " violated by " << value.dump() << ":\n"
                                  << violations;
}

/// A TLS client context trusting exactly the certificate in `certificate_file` (PEM), for servers started
/// with that certificate: the handshake fails unless the server presents it.
inline std::shared_ptr<ssl::context> trusting(const std::string& certificate_file) {
  auto context = std::make_shared<ssl::context>(ssl::context::tls_client);
  context->load_verify_file(certificate_file);
  context->set_verify_mode(ssl::verify_peer);
  return context;
}

/// Connects `stream` to 127.0.0.1:`port`: a TCP socket, or a TLS stream, which then also does its client
/// handshake, verifying the server's certificate for 127.0.0.1 against what its context trusts. Throws
/// beast::system_error when it cannot connect or the certificate is not trusted.
template <class Stream>
void open_stream(Stream& stream, std::uint16_t port) {
  beast::get_lowest_layer(stream).connect({boost::asio::ip::make_address("127.0.0.1"), port});
  if constexpr (std::is_same_v<Stream, TlsSocket>) {
    stream.set_verify_callback(ssl::host_name_verification("127.0.0.1"));
    stream.handshake(ssl::stream_base::client);
  }
}

/// One request on a fresh connection over `stream` (unconnected), the response read to its end.
template <class Stream>
http::response<http::string_body> http_exchange(Stream& stream, std::uint16_t port, http::verb method,
                                                const std::string& target, std::string body,
                                                const std::string& token) {
  open_stream(stream, port);
  http::request<http::string_body> request{method, target, 11};
  request.set(http::field::host, "127.0.0.1");
  if (!token.empty())
    request.set(http::field::authorization, "Bearer " + token);
  request.body() = std::move(body);
  request.prepare_payload();
  http::write(stream, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  beast::error_code ignored;
  beast::get_lowest_layer(stream).shutdown(tcp::socket::shutdown_both, ignored);
  return response;
}

inline http::response<http::string_body> http_request(std::uint16_t port, http::verb method,
                                                      const std::string& target, std::string body = {},
                                                      const std::string& token = {}) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  return http_exchange(socket, port, method, target, std::move(body), token);
}

inline http::response<http::string_body> http_get(std::uint16_t port, const std::string& target) {
  return http_request(port, http::verb::get, target);
}

/// GET `target` with `host` as the Host header (the name a browser would put there), on a fresh connection.
inline http::response<http::string_body> http_get_for_host(std::uint16_t port, const std::string& target,
                                                           const std::string& host) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  open_stream(socket, port);
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, host);
  http::write(socket, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(socket, buffer, response);
  beast::error_code ignored;
  socket.shutdown(tcp::socket::shutdown_both, ignored);
  return response;
}

/// The same request over TLS, trusting `tls`.
inline http::response<http::string_body> https_request(ssl::context& tls, std::uint16_t port,
                                                       http::verb method, const std::string& target,
                                                       std::string body = {}, const std::string& token = {}) {
  boost::asio::io_context io;
  TlsSocket stream(io, tls);
  return http_exchange(stream, port, method, target, std::move(body), token);
}

/// A WebSocket upgrade request on /ws with `extra` headers, sent by hand so that a refusal's status and
/// body can be read (a WebSocket client only reports that the handshake failed).
inline http::response<http::string_body> websocket_upgrade(
    std::uint16_t port, const std::vector<std::pair<http::field, std::string>>& extra) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  open_stream(socket, port);
  http::request<http::empty_body> request{http::verb::get, "/ws", 11};
  request.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  request.set(http::field::upgrade, "websocket");
  request.set(http::field::connection, "Upgrade");
  request.set(http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ==");
  request.set(http::field::sec_websocket_version, "13");
  request.set(http::field::sec_websocket_protocol, "strata.v1");
  for (const auto& [field, value] : extra)
    request.set(field, value);
  http::write(socket, request);
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  http::read_header(socket, buffer, parser);
  if (parser.get().result() != http::status::switching_protocols)
    http::read(socket, buffer, parser);  // a refusal has a body; a 101 has none and the stream begins
  beast::error_code ignored;
  socket.shutdown(tcp::socket::shutdown_both, ignored);
  return parser.release();
}

/// A WebSocket client on /ws that reads JSON messages with a timeout: WsClient over TCP (ws://), WssClient
/// over TLS (wss://).
template <class Stream>
class BasicWsClient {
 public:
  static constexpr bool kTls = std::is_same_v<Stream, TlsSocket>;

  /// Throws beast::system_error when the handshake is refused. `origin`: the Origin header a browser page
  /// would send (none: a script).
  explicit BasicWsClient(std::uint16_t port, std::string subprotocol = "strata.v1",
                         std::string target = "/ws", std::string authorization = {},
                         std::string origin = {}) requires(!kTls)
      : ws_(io_) {
    handshake(port, subprotocol, target, authorization, origin);
  }
  /// Over TLS, trusting `tls`.
  BasicWsClient(ssl::context& tls, std::uint16_t port, std::string subprotocol = "strata.v1",
                std::string target = "/ws", std::string authorization = {}) requires kTls : ws_(io_, tls) {
    handshake(port, subprotocol, target, authorization);
  }

  /// An operator's connection: the token as a second subprotocol, as the browser sends it.
  static std::unique_ptr<BasicWsClient> operator_client(std::uint16_t port,
                                                        const std::string& token) requires(!kTls) {
    return std::make_unique<BasicWsClient>(port, "strata.v1, strata.token." + token);
  }
  static std::unique_ptr<BasicWsClient> operator_client(ssl::context& tls, std::uint16_t port,
                                                        const std::string& token) requires kTls {
    return std::make_unique<BasicWsClient>(tls, port, "strata.v1, strata.token." + token);
  }

  /// One frame as it came: text or binary.
  struct Frame {
    bool binary = false;
    std::string data;
  };

  /// The next frame, text or binary; throws like read().
  Frame read_frame(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    // Asio's blocking reads ignore SO_RCVTIMEO, so read asynchronously and bound the wait.
    beast::flat_buffer buffer;
    std::optional<beast::error_code> result;
    ws_.async_read(buffer, [&result](beast::error_code error, std::size_t) { result = error; });
    io_.restart();
    io_.run_for(timeout);
    if (!result) {
      beast::error_code ignored;
      beast::get_lowest_layer(ws_).close(ignored);
      io_.restart();
      io_.run();
      throw Timeout("no WebSocket message within the timeout");
    }
    if (*result)
      throw beast::system_error(*result);
    return {ws_.got_binary(), beast::buffers_to_string(buffer.data())};
  }

  /// Binary frames read() passed over, oldest first.
  std::vector<std::string>& binary_frames() { return binary_frames_; }

  [[nodiscard]] const websocket::response_type& handshake_response() const { return response_; }

  /// The next message as JSON, checked against its schema in proto/ (a mismatch fails the test);
  /// throws beast::system_error on close or error, Timeout on timeout.
  /// Binary frames (map tiles, the occupancy image) are kept aside in binary_frames().
  nlohmann::json read(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    Frame frame = read_frame(timeout);
    while (frame.binary) {
      binary_frames_.push_back(std::move(frame.data));
      frame = read_frame(timeout);
    }
    nlohmann::json message = nlohmann::json::parse(frame.data);
    const std::string violations = protocol_schemas().server_message_violations(message);
    EXPECT_TRUE(violations.empty()) << "server sent " << message.dump() << ":\n" << violations;
    return message;
  }

  /// Reads until a message with `op` arrives (at most `limit` messages).
  nlohmann::json read_op(const std::string& op, int limit = 200) {
    for (int i = 0; i < limit; ++i) {
      nlohmann::json message = read();
      if (message.value("op", "") == op)
        return message;
    }
    throw std::runtime_error("no '" + op + "' message within " + std::to_string(limit) + " messages");
  }

  void send_text(const std::string& text) {
    ws_.text(true);
    ws_.write(boost::asio::buffer(text));
  }
  void send_binary(const std::string& bytes) {
    ws_.binary(true);
    ws_.write(boost::asio::buffer(bytes));
  }

  /// Whether the server has closed the connection (reads until an error, at most `limit` messages).
  bool closed_by_server(int limit = 1000) {
    try {
      for (int i = 0; i < limit; ++i)
        read();
    } catch (const beast::system_error&) {
      return true;
    }
    return false;
  }

 private:
  void handshake(std::uint16_t port, const std::string& subprotocol, const std::string& target,
                 const std::string& authorization, const std::string& origin = {}) {
    open_stream(ws_.next_layer(), port);
    ws_.set_option(websocket::stream_base::decorator(
        [subprotocol, authorization, origin](websocket::request_type& request) {
          if (!subprotocol.empty())
            request.set(http::field::sec_websocket_protocol, subprotocol);
          if (!authorization.empty())
            request.set(http::field::authorization, authorization);
          if (!origin.empty())
            request.set(http::field::origin, origin);
        }));
    // Host with the port, as browsers send it (the same-origin check compares it with Origin).
    ws_.handshake(response_, "127.0.0.1:" + std::to_string(port), target);
  }

  boost::asio::io_context io_;
  websocket::stream<Stream> ws_;
  websocket::response_type response_;
  std::vector<std::string> binary_frames_;
};

using WsClient = BasicWsClient<tcp::socket>;
using WssClient = BasicWsClient<TlsSocket>;

/// Reads status messages until `done` holds for one; returns it. Fails after many minutes of messages.
template <typename Condition>
nlohmann::json wait_for_status(WsClient& client, Condition done) {
  nlohmann::json last;
  for (int i = 0; i < 100000; ++i) {
    const auto message = client.read(std::chrono::seconds(60));
    if (message["op"] != "status")
      continue;
    last = message;
    if (done(message))
      return message;
  }
  throw std::runtime_error("the status never reached the condition; last: " + last.dump());
}

}  // namespace strata::testing

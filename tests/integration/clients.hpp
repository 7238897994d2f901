#pragma once

// Real clients for integration tests: an HTTP client and a WebSocket client over loopback TCP, plain or
// TLS (https://, wss://), all from Boost.Beast, talking to the strata process exactly as a user's script
// would. The TLS variants verify the server's certificate against one trusted certificate file.
//
// Only declarations here: the Beast, Asio and OpenSSL code is instantiated once, in clients.cpp, instead of
// in every test file (it was most of the integration tests' compile time).

#include <boost/beast/http/field.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/status.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/verb.hpp>
#include <boost/system/system_error.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "integration/protocol_schemas.hpp"

namespace boost::asio::ssl {
class context;
}
namespace boost::asio::ip {
class tcp;
}

namespace strata::testing {

namespace beast = boost::beast;
namespace http = beast::http;
namespace ssl = boost::asio::ssl;
using tcp = boost::asio::ip::tcp;
using HttpResponse = http::response<http::string_body>;

struct Timeout : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The schemas of proto/, loaded once per test process.
ProtocolSchemas& protocol_schemas();

/// Adds a test failure when `value` does not match `proto/schemas/<group>/<name>.schema.json`.
void expect_schema(const std::string& group, const std::string& name, const nlohmann::json& value);

/// A TLS client context trusting exactly the certificate in `certificate_file` (PEM), for servers started
/// with that certificate: the handshake fails unless the server presents it.
std::shared_ptr<ssl::context> trusting(const std::string& certificate_file);

/// One request on a fresh connection to 127.0.0.1:`port`, the response read to its end. Throws
/// beast::system_error when it cannot connect.
HttpResponse http_request(std::uint16_t port, http::verb method, const std::string& target,
                          std::string body = {}, const std::string& token = {});

HttpResponse http_get(std::uint16_t port, const std::string& target);

/// GET `target` with `host` as the Host header (the name a browser would put there), on a fresh connection.
HttpResponse http_get_for_host(std::uint16_t port, const std::string& target, const std::string& host);

/// The same request over TLS, trusting `tls`: verifies the server's certificate for 127.0.0.1.
HttpResponse https_request(ssl::context& tls, std::uint16_t port, http::verb method,
                           const std::string& target, std::string body = {}, const std::string& token = {});

/// A WebSocket upgrade request on /ws with `extra` headers, sent by hand so that a refusal's status and
/// body can be read (a WebSocket client only reports that the handshake failed).
HttpResponse websocket_upgrade(std::uint16_t port,
                               const std::vector<std::pair<http::field, std::string>>& extra);

/// A WebSocket client on /ws that reads JSON messages with a timeout, over TCP (ws://) or TLS (wss://).
class WsClient {
 public:
  /// Throws beast::system_error when the handshake is refused. `origin`: the Origin header a browser page
  /// would send (none: a script).
  explicit WsClient(std::uint16_t port, const std::string& subprotocol = "strata.v1",
                    const std::string& target = "/ws", const std::string& authorization = {},
                    const std::string& origin = {});
  /// Over TLS, trusting `tls`.
  WsClient(ssl::context& tls, std::uint16_t port, const std::string& subprotocol = "strata.v1",
           const std::string& target = "/ws", const std::string& authorization = {});
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  /// An operator's connection: the token as a second subprotocol, as the browser sends it.
  static std::unique_ptr<WsClient> operator_client(std::uint16_t port, const std::string& token);
  static std::unique_ptr<WsClient> operator_client(ssl::context& tls, std::uint16_t port,
                                                   const std::string& token);

  /// One frame as it came: text or binary.
  struct Frame {
    bool binary = false;
    std::string data;
  };

  /// The next frame, text or binary; throws like read().
  Frame read_frame(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  /// Binary frames read() passed over, oldest first.
  std::vector<std::string>& binary_frames() { return binary_frames_; }

  [[nodiscard]] const HttpResponse& handshake_response() const;

  /// The next message as JSON, checked against its schema in proto/ (a mismatch fails the test);
  /// throws beast::system_error on close or error, Timeout on timeout.
  /// Binary frames (map tiles, the occupancy image) are kept aside in binary_frames().
  nlohmann::json read(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  /// Reads until a message with `op` arrives (at most `limit` messages).
  nlohmann::json read_op(const std::string& op, int limit = 200);

  void send_text(const std::string& text);
  void send_binary(const std::string& bytes);

  /// Whether the server has closed the connection (reads until an error, at most `limit` messages).
  bool closed_by_server(int limit = 1000);

  /// The WebSocket stream over TCP or TLS (clients.cpp).
  class Connection;

 private:
  std::unique_ptr<Connection> connection_;
  std::vector<std::string> binary_frames_;
};

/// The same client; the name says a test connects over TLS.
using WssClient = WsClient;

/// Stamps teleop commands as the clients do (proto/PROTOCOL.md, "Teleoperation"): the server clock from
/// hello's clock_ms plus the time elapsed here since it arrived, and a sequence number.
class TeleopStamper {
 public:
  explicit TeleopStamper(const nlohmann::json& hello)
      : clock_at_hello_ms_(hello.at("clock_ms").get<double>()),
        hello_arrived_(std::chrono::steady_clock::now()) {}
  /// A teleop at (v, w) sent now; with an `id` when not null (it asks for an ack).
  [[nodiscard]] std::string command(double v, double w, const nlohmann::json& id = nullptr) {
    const double elapsed_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - hello_arrived_).count();
    nlohmann::json command{
        {"op", "teleop"}, {"v", v}, {"w", w}, {"seq", ++seq_}, {"t", clock_at_hello_ms_ + elapsed_ms}};
    if (!id.is_null())
      command["id"] = id;
    return command.dump();
  }

 private:
  double clock_at_hello_ms_;
  std::chrono::steady_clock::time_point hello_arrived_;
  std::uint64_t seq_ = 0;
};

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

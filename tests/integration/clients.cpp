#include "integration/clients.hpp"

#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <optional>
#include <type_traits>

namespace strata::testing {

namespace websocket = beast::websocket;
using TlsSocket = ssl::stream<tcp::socket>;

ProtocolSchemas& protocol_schemas() {
  static ProtocolSchemas schemas;
  return schemas;
}

void expect_schema(const std::string& group, const std::string& name, const nlohmann::json& value) {
  const std::string violations = protocol_schemas().violations(group, name, value);
  EXPECT_TRUE(violations.empty()) << group << "/" << name << " violated by " << value.dump() << ":\n"
                                  << violations;
}

std::shared_ptr<ssl::context> trusting(const std::string& certificate_file) {
  auto context = std::make_shared<ssl::context>(ssl::context::tls_client);
  context->load_verify_file(certificate_file);
  context->set_verify_mode(ssl::verify_peer);
  return context;
}

namespace {

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
HttpResponse http_exchange(Stream& stream, std::uint16_t port, http::verb method, const std::string& target,
                           std::string body, const std::string& token) {
  open_stream(stream, port);
  http::request<http::string_body> request{method, target, 11};
  request.set(http::field::host, "127.0.0.1");
  if (!token.empty())
    request.set(http::field::authorization, "Bearer " + token);
  request.body() = std::move(body);
  request.prepare_payload();
  http::write(stream, request);
  beast::flat_buffer buffer;
  HttpResponse response;
  http::read(stream, buffer, response);
  beast::error_code ignored;
  beast::get_lowest_layer(stream).shutdown(tcp::socket::shutdown_both, ignored);
  return response;
}

}  // namespace

HttpResponse http_request(std::uint16_t port, http::verb method, const std::string& target, std::string body,
                          const std::string& token) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  return http_exchange(socket, port, method, target, std::move(body), token);
}

HttpResponse http_get(std::uint16_t port, const std::string& target) {
  return http_request(port, http::verb::get, target);
}

HttpResponse http_get_for_host(std::uint16_t port, const std::string& target, const std::string& host) {
  boost::asio::io_context io;
  tcp::socket socket(io);
  open_stream(socket, port);
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, host);
  http::write(socket, request);
  beast::flat_buffer buffer;
  HttpResponse response;
  http::read(socket, buffer, response);
  beast::error_code ignored;
  socket.shutdown(tcp::socket::shutdown_both, ignored);
  return response;
}

HttpResponse https_request(ssl::context& tls, std::uint16_t port, http::verb method,
                           const std::string& target, std::string body, const std::string& token) {
  boost::asio::io_context io;
  TlsSocket stream(io, tls);
  return http_exchange(stream, port, method, target, std::move(body), token);
}

HttpResponse websocket_upgrade(std::uint16_t port,
                               const std::vector<std::pair<http::field, std::string>>& extra) {
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

/// What WsClient needs of its stream, whatever the transport.
class WsClient::Connection {
 public:
  virtual ~Connection() = default;
  virtual Frame read_frame(std::chrono::milliseconds timeout) = 0;
  virtual void write(const std::string& data, bool binary) = 0;
  [[nodiscard]] const HttpResponse& handshake_response() const { return response_; }

 protected:
  HttpResponse response_;
};

namespace {

template <class Stream>
class StreamConnection final : public WsClient::Connection {
 public:
  template <class... StreamArgs>
  StreamConnection(std::uint16_t port, const std::string& subprotocol, const std::string& target,
                   const std::string& authorization, const std::string& origin, StreamArgs&... stream_args)
      : ws_(io_, stream_args...) {
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

  WsClient::Frame read_frame(std::chrono::milliseconds timeout) override {
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

  void write(const std::string& data, bool binary) override {
    ws_.binary(binary);
    ws_.write(boost::asio::buffer(data));
  }

 private:
  boost::asio::io_context io_;
  websocket::stream<Stream> ws_;
};

}  // namespace

WsClient::WsClient(std::uint16_t port, const std::string& subprotocol, const std::string& target,
                   const std::string& authorization, const std::string& origin)
    : connection_(std::make_unique<StreamConnection<tcp::socket>>(port, subprotocol, target, authorization,
                                                                  origin)) {}

WsClient::WsClient(ssl::context& tls, std::uint16_t port, const std::string& subprotocol,
                   const std::string& target, const std::string& authorization)
    : connection_(std::make_unique<StreamConnection<TlsSocket>>(port, subprotocol, target, authorization,
                                                                std::string{}, tls)) {}

WsClient::~WsClient() = default;

std::unique_ptr<WsClient> WsClient::operator_client(std::uint16_t port, const std::string& token) {
  return std::make_unique<WsClient>(port, "strata.v1, strata.token." + token);
}

std::unique_ptr<WsClient> WsClient::operator_client(ssl::context& tls, std::uint16_t port,
                                                    const std::string& token) {
  return std::make_unique<WsClient>(tls, port, "strata.v1, strata.token." + token);
}

WsClient::Frame WsClient::read_frame(std::chrono::milliseconds timeout) {
  return connection_->read_frame(timeout);
}

const HttpResponse& WsClient::handshake_response() const {
  return connection_->handshake_response();
}

nlohmann::json WsClient::read(std::chrono::milliseconds timeout) {
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

nlohmann::json WsClient::read_op(const std::string& op, int limit) {
  for (int i = 0; i < limit; ++i) {
    nlohmann::json message = read();
    if (message.value("op", "") == op)
      return message;
  }
  throw std::runtime_error("no '" + op + "' message within " + std::to_string(limit) + " messages");
}

void WsClient::send_text(const std::string& text) {
  connection_->write(text, false);
}
void WsClient::send_binary(const std::string& bytes) {
  connection_->write(bytes, true);
}

bool WsClient::closed_by_server(int limit) {
  try {
    for (int i = 0; i < limit; ++i)
      read();
  } catch (const beast::system_error&) {
    return true;
  }
  return false;
}

}  // namespace strata::testing

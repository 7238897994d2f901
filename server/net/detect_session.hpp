#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <memory>
#include <optional>

#include "server/net/connection_places.hpp"
#include "server/net/server_context.hpp"
#include "server/net/transport.hpp"
#include "server/protocol/http_types.hpp"

namespace strata::net {

/// The start of every connection when TLS is configured: reads the first bytes and decides. A TLS
/// ClientHello goes on to an HttpSession over TLS (https://, wss://). Anything else is refused: a plain
/// HTTP request is answered with 400 and a REST error saying to use https://, and the connection closed,
/// without routing it (no API, no app, no WebSocket). Tokens travel in headers, so nothing is served in
/// the clear once TLS is on. Runs on the socket's strand.
class DetectSession : public std::enable_shared_from_this<DetectSession> {
 public:
  DetectSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<boost::asio::ssl::context> tls,
                std::shared_ptr<ServerContext> context, ConnectionPlaces places);
  void run();

 private:
  void on_detect(boost::beast::error_code error, bool is_tls);
  void on_plain_header(boost::beast::error_code error, std::size_t bytes);
  void on_refusal_written(boost::beast::error_code error, std::size_t bytes);
  void drain();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<boost::asio::ssl::context> tls_;
  std::shared_ptr<ServerContext> context_;
  std::optional<http::request_parser<http::empty_body>> plain_request_;
  std::shared_ptr<protocol::HttpResponse> refusal_;
  std::optional<ConnectionPlaces> places_;  // handed on to the HttpSession
};

}  // namespace strata::net

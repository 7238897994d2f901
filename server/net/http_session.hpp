#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <memory>
#include <optional>

#include "server/net/connection_places.hpp"
#include "server/net/server_context.hpp"
#include "server/net/transport.hpp"
#include "server/protocol/http_types.hpp"

namespace strata::net {

/// One HTTP/1.1 connection: reads requests, answers them through the router, and hands the stream to a
/// WebSocketSession when a client upgrades on /ws. Runs on its socket's strand. Over TLS it first
/// completes the server handshake and ends with a TLS close_notify; the rest is the same code.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  /// `buffer`: bytes already read from the connection (by the TLS detection), used before reading more.
  /// `places`: the connection's places under the limits, given back when the session ends (after an
  /// upgrade, the WebSocket session takes its address's place and holds a WebSocket place instead of the
  /// HTTP one).
  HttpSession(Stream&& stream, boost::beast::flat_buffer&& buffer, std::shared_ptr<ServerContext> context,
              ConnectionPlaces places);
  void run();

 private:
  void on_handshake(boost::beast::error_code error, std::size_t bytes_used);
  void read_next();
  void on_read(boost::beast::error_code error, std::size_t bytes);
  void upgrade_to_websocket();
  /// Answers a request that works on the whole map on ServerContext::map_work, or 503 when that is busy.
  void answer_off_the_network();
  /// A request that could not be read (`error`: the parser's): 400, 413 or 431 with the reason, then closes.
  void refuse_malformed(boost::beast::error_code error);
  void refuse_host();
  /// Writes a JSON error response (its status and body set) and closes the connection after it.
  void send_refusal(protocol::HttpResponse refusal);
  void write(protocol::HttpResponse response);
  void on_write(bool keep_alive, boost::beast::error_code error, std::size_t bytes);
  void shutdown();

  Stream stream_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<ServerContext> context_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<protocol::HttpResponse> response_;  // kept alive until its async_write completes
  ConnectionPlaces places_;
};

extern template class HttpSession<PlainStream>;
extern template class HttpSession<TlsStream>;

}  // namespace strata::net

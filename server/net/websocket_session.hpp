#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <memory>
#include <string_view>

#include "server/net/client_hub.hpp"
#include "server/net/http_types.hpp"
#include "server/net/send_queue.hpp"
#include "server/net/server_context.hpp"

namespace strata::net {

/// One WebSocket client on /ws. Everything runs on the session's strand (the executor of its socket);
/// outgoing messages wait in a bounded, coalescing SendQueue with one write in flight.
class WebSocketSession : public ClientConnection, public std::enable_shared_from_this<WebSocketSession> {
 public:
  WebSocketSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<ServerContext> context);
  ~WebSocketSession() override;

  /// Completes the upgrade `request` asked for, then starts streaming.
  void run(HttpRequest request);
  void send(OutgoingMessage message) override;

 private:
  void on_accept(boost::beast::error_code error);
  void read_next();
  void on_read(boost::beast::error_code error, std::size_t bytes);
  void handle_client_message(std::string_view text);
  void enqueue(OutgoingMessage message);
  void write_next();
  void on_write(boost::beast::error_code error, std::size_t bytes);

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<ServerContext> context_;
  SendQueue queue_;
  bool open_ = false;
};

/// Whether an upgrade request's Sec-WebSocket-Protocol list is acceptable: absent, or naming ours.
[[nodiscard]] bool accepts_subprotocol(std::string_view offered);

}  // namespace strata::net

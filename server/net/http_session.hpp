#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <memory>
#include <optional>

#include "server/net/http_types.hpp"
#include "server/net/server_context.hpp"

namespace strata::net {

/// One HTTP/1.1 connection: reads requests, answers them through the router, and hands the socket to
/// a WebSocketSession when a client upgrades on /ws. Runs on its socket's strand.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<ServerContext> context);
  void run();

 private:
  void read_next();
  void on_read(boost::beast::error_code error, std::size_t bytes);
  void upgrade_to_websocket();
  void write(HttpResponse response);
  void on_write(bool keep_alive, boost::beast::error_code error, std::size_t bytes);
  void shutdown();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<ServerContext> context_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<HttpResponse> response_;  // kept alive until its async_write completes
};

}  // namespace strata::net

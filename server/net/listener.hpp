#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <memory>

#include "server/net/server_context.hpp"

namespace strata::net {

/// Accepts TCP connections, each on a fresh strand: without TLS it starts a plain HttpSession; with TLS a
/// DetectSession, which serves TLS and refuses plain HTTP.
class Listener : public std::enable_shared_from_this<Listener> {
 public:
  /// Binds and listens at once, so a bad address or a port in use fails here with a clear error.
  /// `tls`: the server's TLS context (make_tls_context), or null for plain HTTP.
  Listener(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& endpoint,
           std::shared_ptr<ServerContext> context, std::shared_ptr<boost::asio::ssl::context> tls = nullptr);

  void run();
  void stop();
  [[nodiscard]] boost::asio::ip::tcp::endpoint local_endpoint() const { return acceptor_.local_endpoint(); }

 private:
  void accept_next();

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<ServerContext> context_;
  std::shared_ptr<boost::asio::ssl::context> tls_;
};

}  // namespace strata::net

#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <memory>

#include "server/net/server_context.hpp"

namespace strata::net {

/// Accepts TCP connections and starts an HttpSession on a fresh strand for each.
class Listener : public std::enable_shared_from_this<Listener> {
 public:
  /// Binds and listens at once, so a bad address or a port in use fails here with a clear error.
  Listener(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& endpoint,
           std::shared_ptr<ServerContext> context);

  void run();
  void stop();
  [[nodiscard]] boost::asio::ip::tcp::endpoint local_endpoint() const { return acceptor_.local_endpoint(); }

 private:
  void accept_next();

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<ServerContext> context_;
};

}  // namespace strata::net

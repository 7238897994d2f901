#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <cstddef>
#include <memory>
#include <string>

namespace strata::net {

/// A plain HTTP connection over the HTTP connection limit: answered 503 `unavailable` with Retry-After
/// without reading its request (whatever it asked, the answer is the same), then closed. What the client
/// sent is read and dropped until it closes, for at most a few seconds: closing with unread data would
/// reset the connection and the client could lose the answer.
class RefusedConnection : public std::enable_shared_from_this<RefusedConnection> {
 public:
  /// `limit`: the HTTP connection limit, for the message.
  RefusedConnection(boost::asio::ip::tcp::socket&& socket, std::size_t limit);
  void run();

 private:
  void on_written(boost::beast::error_code error, std::size_t bytes);
  void drain();

  boost::beast::tcp_stream stream_;
  std::string response_;
  boost::beast::flat_buffer buffer_;
};

}  // namespace strata::net

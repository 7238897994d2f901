#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <cstddef>
#include <memory>
#include <string>

namespace strata::net {

/// A plain HTTP connection over a connection limit: answered 503 `unavailable` with Retry-After
/// without reading its request (whatever it asked, the answer is the same), then closed. What the client
/// sent is read and dropped until it closes, for at most a few seconds: closing with unread data would
/// reset the connection and the client could lose the answer.
class RefusedConnection : public std::enable_shared_from_this<RefusedConnection> {
 public:
  /// `why`: the error's message, saying which limit.
  RefusedConnection(boost::asio::ip::tcp::socket&& socket, const std::string& why);
  void run();

 private:
  void on_written(boost::beast::error_code error, std::size_t bytes);
  void drain();

  boost::beast::tcp_stream stream_;
  std::string response_;
  boost::beast::flat_buffer buffer_;
};

}  // namespace strata::net

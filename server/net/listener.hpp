#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <memory>

#include "server/net/rate_limiter.hpp"
#include "server/net/server_context.hpp"

namespace strata::net {

/// Accepts TCP connections, each on a fresh strand: without TLS it starts a plain HttpSession; with TLS a
/// DetectSession, which serves TLS and refuses plain HTTP. Every connection holds a place of the HTTP
/// connection limit (ServerContext::http_connections) until it closes or becomes a WebSocket; one more is
/// answered 503 and closed at once. When accepting fails (out of file descriptors: EMFILE, ENFILE) it waits
/// before the next try, 50 ms doubling to 1 s, instead of spinning.
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
  void on_accept_failed(const boost::system::error_code& error);
  void start_session(boost::asio::ip::tcp::socket socket);
  /// Answers 503 with `why` (plain HTTP) or closes (TLS), and logs it at most once per 10 s.
  void refuse(boost::asio::ip::tcp::socket socket, std::string why);

  boost::asio::io_context& io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer accept_retry_;  // the back-off after a failed accept
  std::shared_ptr<ServerContext> context_;
  std::shared_ptr<boost::asio::ssl::context> tls_;
  // Only touched on the acceptor's strand.
  std::chrono::milliseconds accept_delay_{0};  // zero: the last accept succeeded
  std::uint64_t accept_failures_ = 0;          // in the current run of failures
  std::uint64_t refusals_unlogged_ = 0;        // refused at the HTTP limit since the last log line
  // One log line per 10 s at most for each: a flood must not flood the log.
  RateLimiter accept_failure_log_{0.1, 1.0};
  RateLimiter recovery_log_{0.1, 1.0};
  RateLimiter refusal_log_{0.1, 1.0};
};

}  // namespace strata::net

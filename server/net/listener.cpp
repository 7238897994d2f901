#include "server/net/listener.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <utility>

#include "server/net/detect_session.hpp"
#include "server/net/http_session.hpp"
#include "server/net/refused_connection.hpp"

namespace strata::net {
namespace {

constexpr std::chrono::milliseconds kFirstAcceptDelay{50};
constexpr std::chrono::milliseconds kMaxAcceptDelay{1000};

}  // namespace

Listener::Listener(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& endpoint,
                   std::shared_ptr<ServerContext> context, std::shared_ptr<boost::asio::ssl::context> tls)
    : io_(io),
      acceptor_(boost::asio::make_strand(io)),
      accept_retry_(acceptor_.get_executor()),
      context_(std::move(context)),
      tls_(std::move(tls)) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(boost::asio::socket_base::max_listen_connections);
}

void Listener::run() {
  accept_next();
}

void Listener::stop() {
  boost::asio::post(acceptor_.get_executor(), [self = shared_from_this()] {
    boost::system::error_code ignored;
    self->acceptor_.close(ignored);
    self->accept_retry_.cancel();
  });
}

void Listener::accept_next() {
  // Each connection gets its own strand: its handlers never run concurrently, whatever the thread count.
  acceptor_.async_accept(
      boost::asio::make_strand(io_),
      [self = shared_from_this()](boost::system::error_code error, boost::asio::ip::tcp::socket socket) {
        if (error == boost::asio::error::operation_aborted)
          return;
        if (error)
          return self->on_accept_failed(error);
        if (self->accept_failures_ > 0 && self->recovery_log_.allow(RateLimiter::Clock::now()))
          spdlog::info("accepting connections again after {} failed attempts", self->accept_failures_);
        self->accept_delay_ = std::chrono::milliseconds(0);
        self->accept_failures_ = 0;
        self->start_session(std::move(socket));
        self->accept_next();
      });
}

void Listener::on_accept_failed(const boost::system::error_code& error) {
  // Out of descriptors the next accept fails at once too: retrying without a pause spins a core and fills
  // the log. The pending connection stays in the kernel's backlog until a descriptor is free.
  accept_delay_ =
      accept_delay_.count() == 0 ? kFirstAcceptDelay : std::min(accept_delay_ * 2, kMaxAcceptDelay);
  ++accept_failures_;
  // The first failure is logged, then one line per 10 s: a server that keeps running out (and recovering)
  // must not fill the disk with the same line.
  if (accept_failure_log_.allow(RateLimiter::Clock::now())) {
    spdlog::warn("accept failed: {} ({} times in a row; retrying in {} ms)", error.message(),
                 accept_failures_, accept_delay_.count());
  }
  accept_retry_.expires_after(accept_delay_);
  accept_retry_.async_wait([self = shared_from_this()](boost::system::error_code wait_error) {
    if (!wait_error && self->acceptor_.is_open())
      self->accept_next();
  });
}

void Listener::start_session(boost::asio::ip::tcp::socket socket) {
  boost::system::error_code error;
  const auto peer = socket.remote_endpoint(error);
  if (error)
    return;  // gone already
  // The address's limit first: one host that holds its every place must not take the server's too.
  auto address_slot = context_->connections_per_address.try_acquire(peer.address());
  if (!address_slot) {
    context_->metrics.refused_address.fetch_add(1, std::memory_order_relaxed);
    return refuse(std::move(socket), "too many connections from your address: the server takes at most " +
                                         std::to_string(context_->connections_per_address.max()) +
                                         " at once from one address; try again later");
  }
  auto slot = context_->http_connections.try_acquire();
  if (!slot) {
    context_->metrics.http_refused_full.fetch_add(1, std::memory_order_relaxed);
    return refuse(std::move(socket), "too many HTTP connections: the server takes at most " +
                                         std::to_string(context_->http_connections.max()) +
                                         " at once; try again later");
  }
  ConnectionPlaces places{std::move(*address_slot), std::move(*slot)};
  if (tls_) {
    std::make_shared<DetectSession>(std::move(socket), tls_, context_, std::move(places))->run();
  } else {
    std::make_shared<HttpSession<PlainStream>>(PlainStream(std::move(socket)), boost::beast::flat_buffer(),
                                               context_, std::move(places))
        ->run();
  }
}

void Listener::refuse(boost::asio::ip::tcp::socket socket, std::string why) {
  ++refusals_unlogged_;
  if (refusal_log_.allow(RateLimiter::Clock::now())) {
    spdlog::warn(
        "refused {} connection(s), the last one: {} (max-http-connections, "
        "max-connections-per-address)",
        refusals_unlogged_, why);
    refusals_unlogged_ = 0;
  }
  if (tls_) {
    // Nothing can be said without a TLS handshake, which is the work the limit saves: just close.
    boost::system::error_code ignored;
    socket.close(ignored);
    return;
  }
  std::make_shared<RefusedConnection>(std::move(socket), std::move(why))->run();
}

}  // namespace strata::net

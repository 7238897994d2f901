#include "server/net/listener.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <utility>

#include "server/net/detect_session.hpp"
#include "server/net/http_session.hpp"

namespace strata::net {

Listener::Listener(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& endpoint,
                   std::shared_ptr<ServerContext> context, std::shared_ptr<boost::asio::ssl::context> tls)
    : io_(io), acceptor_(boost::asio::make_strand(io)), context_(std::move(context)), tls_(std::move(tls)) {
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
  });
}

void Listener::accept_next() {
  // Each connection gets its own strand: its handlers never run concurrently, whatever the thread count.
  acceptor_.async_accept(
      boost::asio::make_strand(io_),
      [self = shared_from_this()](boost::system::error_code error, boost::asio::ip::tcp::socket socket) {
        if (error) {
          if (error == boost::asio::error::operation_aborted)
            return;
          spdlog::warn("accept failed: {}", error.message());
        } else if (self->tls_) {
          std::make_shared<DetectSession>(std::move(socket), self->tls_, self->context_)->run();
        } else {
          std::make_shared<HttpSession<PlainStream>>(PlainStream(std::move(socket)),
                                                     boost::beast::flat_buffer(), self->context_)
              ->run();
        }
        self->accept_next();
      });
}

}  // namespace strata::net

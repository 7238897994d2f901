#include "server/net/detect_session.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/dispatch.hpp>
#include <boost/beast/core/detect_ssl.hpp>
#include <chrono>
#include <utility>

#include "server/net/http_session.hpp"
#include "server/protocol/messages.hpp"

namespace strata::net {
namespace {

namespace beast = boost::beast;
constexpr auto kDetectTimeout = std::chrono::seconds(10);
constexpr auto kDrainTimeout = std::chrono::seconds(5);

}  // namespace

DetectSession::DetectSession(boost::asio::ip::tcp::socket&& socket,
                             std::shared_ptr<boost::asio::ssl::context> tls,
                             std::shared_ptr<ServerContext> context, ConnectionPlaces places)
    : stream_(std::move(socket)), tls_(std::move(tls)), context_(std::move(context)) {
  places_.emplace(std::move(places));
}

void DetectSession::run() {
  boost::asio::dispatch(stream_.get_executor(), [self = shared_from_this()] {
    self->stream_.expires_after(kDetectTimeout);
    beast::async_detect_ssl(self->stream_, self->buffer_,
                            beast::bind_front_handler(&DetectSession::on_detect, self));
  });
}

void DetectSession::on_detect(beast::error_code error, bool is_tls) {
  if (error)
    return;  // closed or silent: nothing to answer
  if (is_tls) {
    // The bytes read so far are the start of the handshake; the HTTP session hands them to OpenSSL.
    std::make_shared<HttpSession<TlsStream>>(TlsStream(std::move(stream_), *tls_), std::move(buffer_),
                                             context_, std::move(*places_))
        ->run();
    return;
  }
  // Plain text on the TLS port: read the request's header (to answer in HTTP), never its body.
  plain_request_.emplace();
  plain_request_->header_limit(16 * 1024);
  http::async_read_header(stream_, buffer_, *plain_request_,
                          beast::bind_front_handler(&DetectSession::on_plain_header, shared_from_this()));
}

void DetectSession::on_plain_header(beast::error_code error, std::size_t /*bytes*/) {
  if (error)
    return;  // not HTTP either: close
  spdlog::debug("refused a plain HTTP request: this server speaks HTTPS only");
  refusal_ =
      std::make_shared<protocol::HttpResponse>(http::status::bad_request, plain_request_->get().version());
  refusal_->set(http::field::server, "strata");
  refusal_->set(http::field::content_type, "application/json");
  refusal_->body() = protocol::rest_error(
      protocol::ErrorCode::kBadRequest,
      "this server accepts only HTTPS (TLS is configured): use https:// and wss:// on this port");
  refusal_->keep_alive(false);
  refusal_->prepare_payload();
  http::async_write(stream_, *refusal_,
                    beast::bind_front_handler(&DetectSession::on_refusal_written, shared_from_this()));
}

void DetectSession::on_refusal_written(beast::error_code error, std::size_t /*bytes*/) {
  if (error)
    return;
  beast::error_code ignored;
  stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ignored);
  // Read (and drop) what the client still sends, such as a request body, until it closes: closing with
  // unread data would reset the connection, and the client could lose the answer. Bounded in time.
  stream_.expires_after(kDrainTimeout);
  drain();
}

void DetectSession::drain() {
  buffer_.clear();
  stream_.async_read_some(buffer_.prepare(4096),
                          [self = shared_from_this()](beast::error_code error, std::size_t /*bytes*/) {
                            if (!error)
                              self->drain();
                          });
}

}  // namespace strata::net

#include "server/net/http_session.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <chrono>
#include <utility>

#include "server/api/responses.hpp"
#include "server/auth/host_policy.hpp"
#include "server/auth/log_throttle.hpp"
#include "server/auth/request_auth.hpp"
#include "server/auth/security_headers.hpp"
#include "server/net/websocket_session.hpp"
#include "server/protocol/messages.hpp"
#include "server/protocol/protocol.hpp"

namespace strata::net {
namespace {

namespace beast = boost::beast;
constexpr auto kRequestTimeout = std::chrono::seconds(30);
constexpr auto kTlsTimeout = std::chrono::seconds(10);  // handshake and close_notify
constexpr std::uint64_t kMaxRequestBodyBytes = 1024 * 1024;

// What a client's refused requests put into the log, one throttle a kind (LogThrottle).
auth::LogThrottle refused_origin_log;
auth::LogThrottle refused_full_log;
auth::LogThrottle refused_host_log;

}  // namespace

template <class Stream>
HttpSession<Stream>::HttpSession(Stream&& stream, beast::flat_buffer&& buffer,
                                 std::shared_ptr<ServerContext> context, ConnectionPlaces places)
    : stream_(std::move(stream)),
      buffer_(std::move(buffer)),
      context_(std::move(context)),
      places_(std::move(places)) {}

template <class Stream>
void HttpSession<Stream>::run() {
  const auto self = this->shared_from_this();
  boost::asio::dispatch(stream_.get_executor(), [self] {
    if constexpr (kIsTls<Stream>) {
      // The detection already read the start of the ClientHello: the handshake begins with those bytes.
      beast::get_lowest_layer(self->stream_).expires_after(kTlsTimeout);
      self->stream_.async_handshake(boost::asio::ssl::stream_base::server, self->buffer_.data(),
                                    beast::bind_front_handler(&HttpSession::on_handshake, self));
    } else {
      self->read_next();
    }
  });
}

template <class Stream>
void HttpSession<Stream>::on_handshake(beast::error_code error, std::size_t bytes_used) {
  if (error) {
    // A client that does not trust the certificate ends here too: worth a line, not a warning.
    spdlog::debug("TLS handshake failed: {}", error.message());
    return;
  }
  buffer_.consume(bytes_used);
  read_next();
}

template <class Stream>
void HttpSession<Stream>::read_next() {
  parser_.emplace();
  parser_->body_limit(kMaxRequestBodyBytes);
  parser_->header_limit(16 * 1024);
  beast::get_lowest_layer(stream_).expires_after(kRequestTimeout);
  http::async_read(stream_, buffer_, *parser_,
                   beast::bind_front_handler(&HttpSession::on_read, this->shared_from_this()));
}

template <class Stream>
void HttpSession<Stream>::on_read(beast::error_code error, std::size_t /*bytes*/) {
  if (error == http::error::end_of_stream)
    return shutdown();
  if (error) {
    // A request that could not be parsed gets a status saying why before the connection closes; one the
    // client abandoned (closed, timed out mid-message) gets nothing.
    if (error.category() == beast::error_code(http::error::bad_field).category() &&
        error != http::error::partial_message)
      return refuse_malformed(error);
    if (error != beast::error::timeout && error != boost::asio::error::operation_aborted &&
        error != boost::asio::error::connection_reset) {
      spdlog::debug("http read failed: {}", error.message());
    }
    return;
  }
  const protocol::HttpRequest& request = parser_->get();
  context_->metrics.http_requests.fetch_add(1, std::memory_order_relaxed);
  // Two Host headers: the checks below would see the first and a proxy or cache might act on the second.
  if (request.count(http::field::host) > 1) {
    protocol::HttpResponse refusal{http::status::bad_request, request.version()};
    refusal.body() =
        protocol::rest_error(protocol::ErrorCode::kBadRequest, "the request has more than one Host header");
    return send_refusal(std::move(refusal));
  }
  if (!auth::host_allowed(request[http::field::host], context_->services.network.allowed_hosts))
    return refuse_host();
  if (beast::websocket::is_upgrade(request))
    return upgrade_to_websocket();
  if (api::HttpRouter::works_on_the_whole_map(request))
    return answer_off_the_network();
  write(context_->router.handle(request));
}

template <class Stream>
void HttpSession<Stream>::answer_off_the_network() {
  auto place = context_->map_work_places.try_acquire();
  if (!place) {
    auto busy = api::error_response(parser_->get(), http::status::service_unavailable,
                                    protocol::ErrorCode::kUnavailable, ServerContext::map_work_busy());
    busy.set(http::field::retry_after, "5");
    return write(std::move(busy));
  }
  // The parser (and its request) stays as it is until the answer is written: nothing else reads it.
  boost::asio::post(
      context_->map_work, [self = this->shared_from_this(), place = std::move(*place)]() mutable {
        auto response = self->context_->router.handle(self->parser_->get());
        boost::asio::post(self->stream_.get_executor(), [self, response = std::move(response)]() mutable {
          self->write(std::move(response));
        });
      });
}

template <class Stream>
void HttpSession<Stream>::upgrade_to_websocket() {
  const protocol::HttpRequest& request = parser_->get();
  const std::string_view target = request.target();
  protocol::HttpResponse refusal;
  const auto auth = auth::authenticate(request, context_->services.network.operator_token);
  const auto role = auth == auth::AuthOutcome::kOperator ? auth::Role::kOperator : auth::Role::kViewer;
  if (target.substr(0, target.find('?')) != "/ws") {
    refusal = protocol::HttpResponse{http::status::not_found, request.version()};
    refusal.body() = protocol::rest_error(protocol::ErrorCode::kNotFound, "WebSocket endpoint is /ws");
  } else if (!accepts_subprotocol(request[http::field::sec_websocket_protocol])) {
    refusal = protocol::HttpResponse{http::status::bad_request, request.version()};
    refusal.body() = protocol::rest_error(
        protocol::ErrorCode::kBadRequest,
        "unsupported subprotocol; this server speaks " + std::string(protocol::kSubprotocol));
  } else if (!auth::origin_allowed(request, context_->services.network.allowed_origins)) {
    // Before the token: a page from another site gets nothing, not even the answer whether a token is right.
    context_->metrics.ws_refused_origin.fetch_add(1, std::memory_order_relaxed);
    if (const auto held = refused_origin_log.admit())
      spdlog::info(
          "refused a WebSocket from the browser origin {} (not this server's, not in allowed-origins){}",
          auth::loggable(request[http::field::origin]), auth::held_back(*held));
    refusal = protocol::HttpResponse{http::status::forbidden, request.version()};
    refusal.body() = protocol::rest_error(protocol::ErrorCode::kForbidden,
                                          "WebSocket connections from this page's origin are not allowed "
                                          "(the server's allowed-origins option)");
  } else if (auth == auth::AuthOutcome::kBadToken || auth == auth::AuthOutcome::kWrongScheme) {
    // Refused rather than downgraded to watching: the client meant to operate and should know why it can't.
    context_->metrics.auth_failures.fetch_add(1, std::memory_order_relaxed);
    refusal = protocol::HttpResponse{http::status::unauthorized, request.version()};
    refusal.body() =
        protocol::rest_error(protocol::ErrorCode::kUnauthorized, std::string(auth::refusal_reason(auth)));
  } else if (auto slot = context_->websocket_place(role)) {
    beast::get_lowest_layer(stream_).expires_never();  // the WebSocket stream has its own timeouts
    std::make_shared<WebSocketSession<Stream>>(std::move(stream_), context_, role, std::move(*slot),
                                               std::move(places_.address))
        ->run(parser_->release());
    return;
  } else {
    context_->metrics.ws_refused_full.fetch_add(1, std::memory_order_relaxed);
    if (const auto held = refused_full_log.admit())
      spdlog::warn("refused a WebSocket client: {} are connected already, the limit (max-clients){}",
                   context_->websocket_clients.max(), auth::held_back(*held));
    refusal = protocol::HttpResponse{http::status::service_unavailable, request.version()};
    refusal.set(http::field::retry_after, "10");
    refusal.body() = protocol::rest_error(protocol::ErrorCode::kUnavailable,
                                          "too many WebSocket clients: the server takes at most " +
                                              std::to_string(context_->websocket_clients.max()) +
                                              " at once; try again later");
  }
  send_refusal(std::move(refusal));
}

template <class Stream>
void HttpSession<Stream>::refuse_host() {
  // Every request, the app's files and the WebSocket upgrade included: a rebound page must get nothing.
  const protocol::HttpRequest& request = parser_->get();
  context_->metrics.refused_host.fetch_add(1, std::memory_order_relaxed);
  if (const auto held = refused_host_log.admit())
    spdlog::debug("refused a request for the host {} (not this server's, not in allowed-hosts){}",
                  auth::loggable(request[http::field::host]), auth::held_back(*held));
  protocol::HttpResponse refusal{http::status::forbidden, request.version()};
  refusal.body() = protocol::rest_error(protocol::ErrorCode::kForbidden,
                                        "this server does not answer to the host name in the request's Host "
                                        "header (the server's allowed-hosts option)");
  send_refusal(std::move(refusal));
}

template <class Stream>
void HttpSession<Stream>::refuse_malformed(beast::error_code error) {
  http::status status = http::status::bad_request;
  std::string message = "malformed HTTP request: " + error.message();
  if (error == http::error::header_limit) {
    status = http::status::request_header_fields_too_large;
    message = "the request's headers are over 16 KiB";
  } else if (error == http::error::body_limit) {
    status = http::status::payload_too_large;
    message = "the request's body is over 1 MiB";
  }
  protocol::HttpResponse refusal{status, 11};
  refusal.body() = protocol::rest_error(protocol::ErrorCode::kBadRequest, message);
  send_refusal(std::move(refusal));
}

template <class Stream>
void HttpSession<Stream>::send_refusal(protocol::HttpResponse refusal) {
  // A refused request ends the connection: what else the client sent is not read.
  refusal.set(http::field::server, "strata");
  refusal.set(http::field::content_type, "application/json");
  refusal.keep_alive(false);
  refusal.prepare_payload();
  write(std::move(refusal));
}

template <class Stream>
void HttpSession<Stream>::write(protocol::HttpResponse response) {
  auth::add_security_headers(response);  // every response leaves here, refusals too
  response_ = std::make_shared<protocol::HttpResponse>(std::move(response));
  const bool keep_alive = response_->keep_alive();
  http::async_write(stream_, *response_,
                    beast::bind_front_handler(&HttpSession::on_write, this->shared_from_this(), keep_alive));
}

template <class Stream>
void HttpSession<Stream>::on_write(bool keep_alive, beast::error_code error, std::size_t /*bytes*/) {
  response_.reset();
  if (error)
    return;
  if (!keep_alive)
    return shutdown();
  read_next();
}

template <class Stream>
void HttpSession<Stream>::shutdown() {
  if constexpr (kIsTls<Stream>) {
    beast::get_lowest_layer(stream_).expires_after(kTlsTimeout);
    stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
  } else {
    beast::error_code ignored;
    stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ignored);
  }
}

template class HttpSession<PlainStream>;
template class HttpSession<TlsStream>;

}  // namespace strata::net

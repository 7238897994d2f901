#include "server/net/refused_connection.hpp"

#include <boost/asio/dispatch.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <sstream>
#include <utility>

#include "server/protocol/messages.hpp"

namespace strata::net {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
constexpr auto kTimeout = std::chrono::seconds(2);

std::string refusal(const std::string& why) {
  http::response<http::string_body> response{http::status::service_unavailable, 11};
  response.set(http::field::server, "strata");
  response.set(http::field::content_type, "application/json");
  response.set(http::field::retry_after, "10");
  response.body() = protocol::rest_error(protocol::ErrorCode::kUnavailable, why);
  response.keep_alive(false);
  response.prepare_payload();
  std::ostringstream out;
  out << response;
  return out.str();
}

}  // namespace

RefusedConnection::RefusedConnection(boost::asio::ip::tcp::socket&& socket, const std::string& why)
    : stream_(std::move(socket)), response_(refusal(why)) {}

void RefusedConnection::run() {
  boost::asio::dispatch(stream_.get_executor(), [self = shared_from_this()] {
    self->stream_.expires_after(kTimeout);
    boost::asio::async_write(self->stream_, boost::asio::buffer(self->response_),
                             beast::bind_front_handler(&RefusedConnection::on_written, self));
  });
}

void RefusedConnection::on_written(beast::error_code error, std::size_t /*bytes*/) {
  if (error)
    return;
  beast::error_code ignored;
  stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ignored);
  drain();
}

void RefusedConnection::drain() {
  buffer_.clear();
  stream_.async_read_some(buffer_.prepare(4096),
                          [self = shared_from_this()](beast::error_code error, std::size_t) {
                            if (!error)
                              self->drain();
                          });
}

}  // namespace strata::net

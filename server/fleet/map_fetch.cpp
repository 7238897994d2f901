// <utility> first: Boost 1.74's awaitable.hpp uses std::exchange without including it.
// clang-format off
#include <utility>
// clang-format on

#include "server/fleet/map_fetch.hpp"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <exception>

#include "server/fleet/broker_address.hpp"

namespace strata::fleet {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace ssl = asio::ssl;
using asio::use_awaitable;
using tcp = asio::ip::tcp;

/// The request and the response over a connected (and for https, handshaken) stream.
template <class Stream>
asio::awaitable<void> get(Stream& stream, const HttpUrl& url, const FetchLimits& limits, FetchResult& out) {
  http::request<http::empty_body> request{http::verb::get, url.target, 11};
  request.set(http::field::host, url.host.find(':') != std::string::npos ? "[" + url.host + "]" : url.host);
  request.set(http::field::user_agent, "strata");
  co_await http::async_write(stream, request, use_awaitable);
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(limits.max_bytes);
  co_await http::async_read(stream, buffer, parser, use_awaitable);
  const auto& response = parser.get();
  if (response.result() != http::status::ok) {
    out.error = "HTTP " + std::to_string(response.result_int()) + " " + std::string(response.reason());
    co_return;
  }
  out.body = std::move(parser.release().body());
}

asio::awaitable<void> fetch(const HttpUrl& url, const FetchLimits& limits, ssl::context& tls,
                            FetchResult& out) {
  auto executor = co_await asio::this_coro::executor;
  tcp::resolver resolver(executor);
  const auto endpoints = co_await resolver.async_resolve(url.host, std::to_string(url.port), use_awaitable);
  if (!url.tls) {
    beast::tcp_stream stream(executor);
    co_await stream.async_connect(endpoints, use_awaitable);
    co_await get(stream, url, limits, out);
    co_return;
  }
  beast::ssl_stream<beast::tcp_stream> stream(executor, tls);
  // SNI, and the certificate must name the host.
  // SSL_set_tlsext_host_name without its macro's C cast.
  if (SSL_ctrl(stream.native_handle(), SSL_CTRL_SET_TLSEXT_HOSTNAME, TLSEXT_NAMETYPE_host_name,
               const_cast<char*>(url.host.c_str())) != 1)
    throw beast::system_error(static_cast<int>(::ERR_get_error()), asio::error::get_ssl_category());
  stream.set_verify_callback(ssl::host_name_verification(url.host));
  co_await beast::get_lowest_layer(stream).async_connect(endpoints, use_awaitable);
  co_await stream.async_handshake(ssl::stream_base::client, use_awaitable);
  co_await get(stream, url, limits, out);
}

std::optional<HttpUrl> refuse_link(std::string* error, std::string why) {
  if (error != nullptr)
    *error = std::move(why);
  return std::nullopt;
}

}  // namespace

std::optional<HttpUrl> parse_http_url(std::string_view url, std::string* error) {
  HttpUrl parsed;
  if (url.starts_with("http://")) {
    url.remove_prefix(7);
  } else if (url.starts_with("https://")) {
    url.remove_prefix(8);
    parsed.tls = true;
    parsed.port = 443;
  } else {
    return refuse_link(error, "the link must be http:// or https://");
  }
  const std::size_t path = url.find_first_of("/?#");
  const auto host_port = parse_host_port(url.substr(0, path), parsed.port, "link", error);
  if (!host_port)
    return std::nullopt;
  parsed.host = host_port->host;
  parsed.port = host_port->port;
  if (path != std::string_view::npos) {
    std::string_view target = url.substr(path);
    target = target.substr(0, target.find('#'));  // a fragment is the client's, never sent
    parsed.target = target.starts_with('/') ? std::string(target) : "/" + std::string(target);
  }
  if (parsed.target.find_first_of(" \r\n") != std::string::npos)
    return refuse_link(error, "the link's path holds spaces or line breaks");
  return parsed;
}

FetchResult fetch_url(std::string_view url, const FetchLimits& limits) {
  FetchResult result;
  const auto parsed = parse_http_url(url, &result.error);
  if (!parsed)
    return result;
  ssl::context tls(ssl::context::tls_client);
  tls.set_default_verify_paths();
  tls.set_verify_mode(ssl::verify_peer);
  bool done = false;
  asio::io_context io;
  asio::co_spawn(io, fetch(*parsed, limits, tls, result), [&](std::exception_ptr failure) {
    done = true;
    if (!failure)
      return;
    try {
      std::rethrow_exception(failure);
    } catch (const beast::system_error& error) {
      result.error = error.code() == http::error::body_limit
                         ? "the file is larger than " + std::to_string(limits.max_bytes) + " bytes"
                         : error.code().message();
    } catch (const std::exception& error) {
      result.error = error.what();
    }
  });
  // The whole fetch within the timeout: what is still under way then is dropped with the io_context.
  io.run_for(limits.timeout);
  if (!done) {
    result.body.clear();
    result.error = "no answer within " + std::to_string(limits.timeout.count()) + " s";
  }
  if (!result.ok())
    result.body.clear();
  return result;
}

}  // namespace strata::fleet

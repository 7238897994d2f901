#pragma once

#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>
#include <type_traits>

namespace strata::net {

namespace http = boost::beast::http;

/// The two transports a session runs over: plain TCP, or TLS over TCP (serve --tls-cert/--tls-key).
/// The HTTP and WebSocket sessions are templates on these, explicitly instantiated for both.
using PlainStream = boost::beast::tcp_stream;
using TlsStream = boost::beast::ssl_stream<boost::beast::tcp_stream>;

template <class Stream>
inline constexpr bool kIsTls = std::is_same_v<Stream, TlsStream>;

}  // namespace strata::net

#pragma once

#include <boost/beast/http.hpp>

namespace strata::protocol {

namespace http = boost::beast::http;
using HttpRequest = http::request<http::string_body>;
using HttpResponse = http::response<http::string_body>;

}  // namespace strata::protocol

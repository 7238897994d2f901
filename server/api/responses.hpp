#pragma once

#include <string>
#include <string_view>

#include "server/net/http_types.hpp"
#include "server/protocol/messages.hpp"

namespace strata::api {

/// Building REST responses: one place for the headers every answer carries.
[[nodiscard]] net::HttpResponse make_response(const net::HttpRequest& request, net::http::status status,
                                              std::string body, std::string_view content_type);
[[nodiscard]] net::HttpResponse json_response(const net::HttpRequest& request, net::http::status status,
                                              std::string body);
[[nodiscard]] net::HttpResponse error_response(const net::HttpRequest& request, net::http::status status,
                                               protocol::ErrorCode code, std::string_view message);
/// An error whose code came as text from a command (CommandResult); the HTTP status follows the code.
[[nodiscard]] net::HttpResponse command_error(const net::HttpRequest& request, std::string_view code,
                                              std::string_view message);
/// 405 with the Allow header.
[[nodiscard]] net::HttpResponse method_not_allowed(const net::HttpRequest& request, std::string_view allow);

[[nodiscard]] bool is_read(const net::HttpRequest& request);

/// Whether an If-None-Match header value lists `etag` (or is "*"); weak validators compare equal too.
[[nodiscard]] bool etag_matches(std::string_view if_none_match, std::string_view etag);

}  // namespace strata::api

#pragma once

#include <string>
#include <string_view>

#include "server/protocol/http_types.hpp"
#include "server/protocol/messages.hpp"

namespace strata::api {

/// Building REST responses: one place for the headers every answer carries.
[[nodiscard]] protocol::HttpResponse make_response(const protocol::HttpRequest& request,
                                                   protocol::http::status status, std::string body,
                                                   std::string_view content_type);
[[nodiscard]] protocol::HttpResponse json_response(const protocol::HttpRequest& request,
                                                   protocol::http::status status, std::string body);
[[nodiscard]] protocol::HttpResponse error_response(const protocol::HttpRequest& request,
                                                    protocol::http::status status, protocol::ErrorCode code,
                                                    std::string_view message);
/// A command's refusal (CommandResult); the HTTP status follows the code.
[[nodiscard]] protocol::HttpResponse command_error(const protocol::HttpRequest& request, ErrorCode code,
                                                   std::string_view message);
/// 405 with the Allow header.
[[nodiscard]] protocol::HttpResponse method_not_allowed(const protocol::HttpRequest& request,
                                                        std::string_view allow);

[[nodiscard]] bool is_read(const protocol::HttpRequest& request);

/// Whether an If-None-Match header value lists `etag` (or is "*"); weak validators compare equal too.
[[nodiscard]] bool etag_matches(std::string_view if_none_match, std::string_view etag);

}  // namespace strata::api

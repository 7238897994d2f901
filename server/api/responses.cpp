#include "server/api/responses.hpp"

#include <utility>

namespace strata::api {

namespace http = protocol::http;

protocol::HttpResponse make_response(const protocol::HttpRequest& request, http::status status,
                                     std::string body, std::string_view content_type) {
  protocol::HttpResponse response{status, request.version()};
  response.set(http::field::server, "strata");
  response.set(http::field::content_type, content_type);
  response.keep_alive(request.keep_alive());
  response.body() = std::move(body);
  response.prepare_payload();
  if (request.method() == http::verb::head)
    response.body().clear();  // keeps Content-Length
  return response;
}

protocol::HttpResponse json_response(const protocol::HttpRequest& request, http::status status,
                                     std::string body) {
  auto response = make_response(request, status, std::move(body), "application/json");
  response.set(http::field::cache_control, "no-store");
  return response;
}

protocol::HttpResponse error_response(const protocol::HttpRequest& request, http::status status,
                                      protocol::ErrorCode code, std::string_view message) {
  auto response = json_response(request, status, protocol::rest_error(code, message));
  if (status == http::status::unauthorized)
    response.set(http::field::www_authenticate, "Bearer realm=\"strata\"");
  return response;
}

protocol::HttpResponse command_error(const protocol::HttpRequest& request, ErrorCode code,
                                     std::string_view message) {
  http::status status = http::status::internal_server_error;  // io_error, internal
  if (code == ErrorCode::kBadParams || code == ErrorCode::kBadRequest)
    status = http::status::bad_request;
  else if (code == ErrorCode::kNotFound)
    status = http::status::not_found;
  else if (code == ErrorCode::kUnavailable)
    status = http::status::service_unavailable;
  else if (code == ErrorCode::kCorruptFile)
    status = http::status::unprocessable_entity;
  // The message may name a file (not necessarily UTF-8): invalid bytes become U+FFFD, dump() never throws.
  auto response =
      json_response(request, status,
                    nlohmann::json{{"error", {{"code", to_string(code)}, {"message", message}}}}.dump(
                        -1, ' ', false, nlohmann::json::error_handler_t::replace));
  return response;
}

protocol::HttpResponse method_not_allowed(const protocol::HttpRequest& request, std::string_view allow) {
  auto response =
      error_response(request, http::status::method_not_allowed, protocol::ErrorCode::kMethodNotAllowed,
                     "allowed here: " + std::string(allow));
  response.set(http::field::allow, allow);
  return response;
}

bool is_read(const protocol::HttpRequest& request) {
  return request.method() == http::verb::get || request.method() == http::verb::head;
}

bool etag_matches(std::string_view if_none_match, std::string_view etag) {
  while (!if_none_match.empty()) {
    const std::size_t comma = if_none_match.find(',');
    std::string_view item = if_none_match.substr(0, comma);
    while (!item.empty() && item.front() == ' ')
      item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ')
      item.remove_suffix(1);
    if (item.starts_with("W/"))
      item.remove_prefix(2);
    if (item == "*" || item == etag)
      return true;
    if (comma == std::string_view::npos)
      break;
    if_none_match.remove_prefix(comma + 1);
  }
  return false;
}

}  // namespace strata::api

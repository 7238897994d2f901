#include "server/api/http_router.hpp"

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>

#include "server/net/static_files.hpp"
#include "server/protocol/messages.hpp"

namespace strata::api {
namespace {

namespace http = net::http;
using protocol::ErrorCode;

net::HttpResponse make_response(const net::HttpRequest& request, http::status status, std::string body,
                                std::string_view content_type) {
  net::HttpResponse response{status, request.version()};
  response.set(http::field::server, "strata");
  response.set(http::field::content_type, content_type);
  response.keep_alive(request.keep_alive());
  response.body() = std::move(body);
  response.prepare_payload();
  if (request.method() == http::verb::head)
    response.body().clear();  // keeps Content-Length
  return response;
}

net::HttpResponse json_response(const net::HttpRequest& request, http::status status, std::string body) {
  auto response = make_response(request, status, std::move(body), "application/json");
  response.set(http::field::cache_control, "no-store");
  return response;
}

net::HttpResponse error_response(const net::HttpRequest& request, http::status status, ErrorCode code,
                                 std::string_view message) {
  return json_response(request, status, protocol::rest_error(code, message));
}

bool is_read(const net::HttpRequest& request) {
  return request.method() == http::verb::get || request.method() == http::verb::head;
}

}  // namespace

HttpRouter::HttpRouter(const RobotState& robot, const net::ClientHub& hub, std::filesystem::path web_root,
                       std::string sim_world)
    : robot_(robot), hub_(hub), web_root_(std::move(web_root)), sim_world_(std::move(sim_world)) {}

net::HttpResponse HttpRouter::handle(const net::HttpRequest& request) const {
  const std::string_view target = request.target();
  const std::string_view path = target.substr(0, target.find('?'));

  const bool is_api = path == "/healthz" || path.starts_with("/api/");
  if (is_api && !is_read(request)) {
    auto response = error_response(request, http::status::method_not_allowed, ErrorCode::kMethodNotAllowed,
                                   "only GET and HEAD are allowed here");
    response.set(http::field::allow, "GET, HEAD");
    return response;
  }
  if (path == "/healthz")
    return json_response(request, http::status::ok, R"({"status":"ok"})");
  if (path == "/api/v1/info")
    return json_response(request, http::status::ok, protocol::info().dump());
  if (path == "/api/v1/pose") {
    const auto robot = robot_.snapshot();
    if (!robot) {
      return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                            "no pose yet: the robot has not reported");
    }
    return json_response(request, http::status::ok, protocol::pose_fields(*robot).dump());
  }
  if (path == "/api/v1/status") {
    return json_response(request, http::status::ok,
                         protocol::status_fields(robot_.registration(), hub_.size()).dump());
  }
  if (path == "/api/v1/sim/world" && !sim_world_.empty()) {
    return json_response(request, http::status::ok, sim_world_);
  }
  if (is_api) {
    return error_response(request, http::status::not_found, ErrorCode::kNotFound,
                          "no such endpoint: " + std::string(path));
  }
  return serve_static(request, path);
}

net::HttpResponse HttpRouter::serve_static(const net::HttpRequest& request, std::string_view path) const {
  if (!is_read(request)) {
    auto response = make_response(request, http::status::method_not_allowed, "method not allowed\n",
                                  "text/plain; charset=utf-8");
    response.set(http::field::allow, "GET, HEAD");
    return response;
  }
  const auto file = net::resolve_static_path(web_root_, path);
  if (!file) {
    return make_response(request, http::status::not_found, "not found\n", "text/plain; charset=utf-8");
  }
  std::ifstream stream(*file, std::ios::binary);
  if (!stream) {
    return make_response(request, http::status::not_found, "not found\n", "text/plain; charset=utf-8");
  }
  std::string body{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
  auto response = make_response(request, http::status::ok, std::move(body), net::mime_type(*file));
  // Vite names bundled assets by content hash: they never change under the same name.
  response.set(http::field::cache_control,
               path.starts_with("/assets/") ? "public, max-age=31536000, immutable" : "no-cache");
  return response;
}

}  // namespace strata::api

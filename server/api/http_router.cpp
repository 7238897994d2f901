#include "server/api/http_router.hpp"

#include <spdlog/spdlog.h>

#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <utility>

#include "server/api/responses.hpp"
#include "server/api/static_files.hpp"
#include "server/auth/log_throttle.hpp"
#include "server/auth/request_auth.hpp"
#include "server/protocol/messages.hpp"

namespace strata::api {

namespace http = protocol::http;
using protocol::ErrorCode;

HttpRouter::HttpRouter(const ServerServices& services, const streams::ClientHub& hub,
                       const streams::StatusStream& status, const streams::ServerMetrics& metrics)
    : services_(services),
      hub_(hub),
      status_(status),
      metrics_(metrics),
      sim_world_(services.sim_world ? protocol::sim_world(*services.sim_world).dump() : std::string()) {}

protocol::HttpResponse HttpRouter::handle(const protocol::HttpRequest& request) const {
  const std::string_view target = request.target();
  const std::size_t question = target.find('?');
  const std::string_view path = target.substr(0, question);
  const std::string_view query =
      question == std::string_view::npos ? std::string_view() : target.substr(question + 1);

  // A request that makes an endpoint throw gets a 500; the exception must not unwind into the session's
  // I/O thread and end the server. (The fuzz target counts a 500 as a failure, so such bugs still show.)
  try {
    if (path == "/healthz" || path == "/metrics" || path.starts_with("/api/")) {
      if (auto response = route_api(request, path, query))
        return std::move(*response);
      return error_response(request, http::status::not_found, ErrorCode::kNotFound,
                            "no such endpoint: " + std::string(path));
    }
    return serve_static(request, path);
  } catch (const std::exception& error) {
    static auth::LogThrottle internal_errors_log;
    if (const auto held = internal_errors_log.admit())
      spdlog::error("{} {}: {}{}", std::string(request.method_string()), auth::loggable(path), error.what(),
                    auth::held_back(*held));
    return error_response(request, http::status::internal_server_error, ErrorCode::kInternal,
                          "internal error");
  }
}

namespace {

/// "/api/v1/maps/{name}/versions/{version}": the name and the version.
std::optional<std::pair<std::string_view, std::string_view>> map_version_of(std::string_view path) {
  constexpr std::string_view kPrefix = "/api/v1/maps/";
  constexpr std::string_view kVersions = "/versions/";
  if (!path.starts_with(kPrefix))
    return std::nullopt;
  path.remove_prefix(kPrefix.size());
  const std::size_t at = path.find(kVersions);
  if (at == 0 || at == std::string_view::npos)
    return std::nullopt;
  const std::string_view version = path.substr(at + kVersions.size());
  if (version.empty() || version.find('/') != std::string_view::npos)
    return std::nullopt;
  return std::pair{path.substr(0, at), version};
}

}  // namespace

bool HttpRouter::works_on_the_whole_map(const protocol::HttpRequest& request) {
  const std::string_view target = request.target();
  const std::string_view path = target.substr(0, target.find('?'));
  if (path == "/api/v1/map")
    return true;
  if (map_version_of(path))
    return true;  // reads a whole map file
  // POST /api/v1/maps saves, POST /api/v1/maps/{name}/load loads; GET only lists.
  return request.method() == http::verb::post &&
         (path == "/api/v1/maps" || path.starts_with("/api/v1/maps/"));
}

std::optional<protocol::HttpResponse> HttpRouter::route_api(const protocol::HttpRequest& request,
                                                            std::string_view path,
                                                            std::string_view query) const {
  // Read-only endpoints first: one Allow list for all of them.
  const auto read_only = [&](auto&& answer) -> protocol::HttpResponse {
    if (!is_read(request))
      return method_not_allowed(request, "GET, HEAD");
    return answer();
  };
  if (path == "/healthz")
    return read_only([&] { return json_response(request, http::status::ok, R"({"status":"ok"})"); });
  if (path == "/metrics")
    return read_only([&] { return metrics(request); });
  if (path == "/api/v1/info")
    return read_only([&] { return json_response(request, http::status::ok, protocol::info().dump()); });
  if (path == "/api/v1/pose") {
    return read_only([&] {
      const auto robot = services_.robot->snapshot();
      if (!robot) {
        return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                              "no pose yet: the robot has not reported");
      }
      return json_response(request, http::status::ok, protocol::pose_fields(*robot).dump());
    });
  }
  if (path == "/api/v1/pose/estimate")
    return pose_estimate(request);
  if (path == "/api/v1/imu-calibration")
    return imu_calibration(request);
  if (path == "/api/v1/status")
    return read_only([&] { return json_response(request, http::status::ok, status_.fields().dump()); });
  if (path == "/api/v1/sim/world" && !sim_world_.empty())
    return read_only([&] { return json_response(request, http::status::ok, sim_world_); });
  if (path == "/api/v1/goal")
    return goal(request);
  if (path == "/api/v1/path")
    return read_only([&] { return this->path(request); });
  if (path == "/api/v1/map")
    return read_only([&] { return map_download(request, query); });
  if (path == "/api/v1/occupancy")
    return read_only([&] { return occupancy(request); });
  if (path == "/api/v1/tiles")
    return read_only([&] { return tile_index(request); });
  if (path.starts_with("/api/v1/tiles/"))
    return read_only([&] { return tile(request, path.substr(std::string_view("/api/v1/tiles/").size())); });
  if (path == "/api/v1/map-versions")
    return read_only([&] { return map_version_list(request); });
  if (const auto version = map_version_of(path))  // anyone may fetch a version, as the map's download
    return read_only([&] { return map_version(request, version->first, version->second); });
  if (path == "/api/v1/maps" || path.starts_with("/api/v1/maps/"))
    return maps(request, path.substr(std::string_view("/api/v1/maps").size()));
  return std::nullopt;
}

std::optional<protocol::HttpResponse> HttpRouter::require_operator(
    const protocol::HttpRequest& request) const {
  const auth::AuthOutcome outcome = auth::authenticate(request, services_.network.operator_token);
  switch (outcome) {
    case auth::AuthOutcome::kOperator:
      return std::nullopt;
    case auth::AuthOutcome::kBadToken:
    case auth::AuthOutcome::kWrongScheme:
      return error_response(request, http::status::unauthorized, ErrorCode::kUnauthorized,
                            std::string(auth::refusal_reason(outcome)));
    case auth::AuthOutcome::kViewer:
      break;
  }
  return error_response(request, http::status::unauthorized, ErrorCode::kUnauthorized,
                        "this needs the operator token (Authorization: Bearer <token>)");
}

protocol::HttpResponse HttpRouter::serve_static(const protocol::HttpRequest& request,
                                                std::string_view path) const {
  if (!is_read(request)) {
    auto response = make_response(request, http::status::method_not_allowed, "method not allowed\n",
                                  "text/plain; charset=utf-8");
    response.set(http::field::allow, "GET, HEAD");
    return response;
  }
  const auto file = api::resolve_static_path(services_.network.web_root, path);
  if (!file) {
    return make_response(request, http::status::not_found, "not found\n", "text/plain; charset=utf-8");
  }
  std::ifstream stream(*file, std::ios::binary);
  if (!stream) {
    return make_response(request, http::status::not_found, "not found\n", "text/plain; charset=utf-8");
  }
  std::string body{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
  auto response = make_response(request, http::status::ok, std::move(body), api::mime_type(*file));
  // Vite names bundled assets by content hash: they never change under the same name.
  response.set(http::field::cache_control,
               path.starts_with("/assets/") ? "public, max-age=31536000, immutable" : "no-cache");
  return response;
}

}  // namespace strata::api

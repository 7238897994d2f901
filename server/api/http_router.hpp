#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "server/control/server_services.hpp"
#include "server/protocol/http_types.hpp"
#include "server/streams/client_hub.hpp"
#include "server/streams/server_metrics.hpp"
#include "server/streams/status_stream.hpp"

namespace strata::api {

/// Answers every plain HTTP request: REST under /api/v1 (proto/openapi.yaml), /healthz, /metrics and the
/// web app's static files. Pure request-in, response-out; the session owns the socket.
class HttpRouter {
 public:
  HttpRouter(const ServerServices& services, const streams::ClientHub& hub,
             const streams::StatusStream& status, const streams::ServerMetrics& metrics);

  [[nodiscard]] protocol::HttpResponse handle(const protocol::HttpRequest& request) const;
  /// Whether answering `request` works on the whole map: a download, a save, a load. That takes seconds on
  /// a big map, so the sessions answer it off the network threads, a few at a time.
  [[nodiscard]] static bool works_on_the_whole_map(const protocol::HttpRequest& request);

 private:
  [[nodiscard]] std::optional<protocol::HttpResponse> route_api(const protocol::HttpRequest& request,
                                                                std::string_view path,
                                                                std::string_view query) const;
  [[nodiscard]] protocol::HttpResponse serve_static(const protocol::HttpRequest& request,
                                                    std::string_view path) const;
  /// nullopt when the request carries the operator token; else the 401 to answer with.
  [[nodiscard]] std::optional<protocol::HttpResponse> require_operator(
      const protocol::HttpRequest& request) const;

  // api/goal_endpoints.cpp
  [[nodiscard]] protocol::HttpResponse goal(const protocol::HttpRequest& request) const;
  [[nodiscard]] protocol::HttpResponse path(const protocol::HttpRequest& request) const;
  [[nodiscard]] protocol::HttpResponse pose_estimate(const protocol::HttpRequest& request) const;
  [[nodiscard]] protocol::HttpResponse imu_calibration(const protocol::HttpRequest& request) const;
  // api/map_endpoints.cpp
  [[nodiscard]] protocol::HttpResponse map_download(const protocol::HttpRequest& request,
                                                    std::string_view query) const;
  [[nodiscard]] protocol::HttpResponse occupancy(const protocol::HttpRequest& request) const;
  [[nodiscard]] protocol::HttpResponse tile_index(const protocol::HttpRequest& request) const;
  [[nodiscard]] protocol::HttpResponse tile(const protocol::HttpRequest& request,
                                            std::string_view coordinates) const;
  [[nodiscard]] protocol::HttpResponse maps(const protocol::HttpRequest& request,
                                            std::string_view rest) const;
  // api/map_version_endpoints.cpp
  [[nodiscard]] protocol::HttpResponse map_version_list(const protocol::HttpRequest& request) const;
  [[nodiscard]] protocol::HttpResponse map_version(const protocol::HttpRequest& request,
                                                   std::string_view name, std::string_view version) const;
  // api/metrics_endpoint.cpp
  [[nodiscard]] protocol::HttpResponse metrics(const protocol::HttpRequest& request) const;

  const ServerServices& services_;
  const streams::ClientHub& hub_;
  const streams::StatusStream& status_;
  const streams::ServerMetrics& metrics_;
  std::string sim_world_;  // GET /api/v1/sim/world, encoded once; empty for a real robot
};

}  // namespace strata::api

#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "server/net/client_hub.hpp"
#include "server/net/http_types.hpp"
#include "server/net/server_metrics.hpp"
#include "server/net/server_services.hpp"
#include "server/streams/status_stream.hpp"

namespace strata::api {

/// Answers every plain HTTP request: REST under /api/v1 (proto/openapi.yaml), /healthz, /metrics and the
/// web app's static files. Pure request-in, response-out; the session owns the socket.
class HttpRouter {
 public:
  HttpRouter(const net::ServerServices& services, const net::ClientHub& hub,
             const streams::StatusStream& status, const net::ServerMetrics& metrics);

  [[nodiscard]] net::HttpResponse handle(const net::HttpRequest& request) const;

 private:
  [[nodiscard]] std::optional<net::HttpResponse> route_api(const net::HttpRequest& request,
                                                           std::string_view path,
                                                           std::string_view query) const;
  [[nodiscard]] net::HttpResponse serve_static(const net::HttpRequest& request, std::string_view path) const;
  /// nullopt when the request carries the operator token; else the 401 to answer with.
  [[nodiscard]] std::optional<net::HttpResponse> require_operator(const net::HttpRequest& request) const;

  // api/goal_endpoints.cpp
  [[nodiscard]] net::HttpResponse goal(const net::HttpRequest& request) const;
  [[nodiscard]] net::HttpResponse path(const net::HttpRequest& request) const;
  // api/map_endpoints.cpp
  [[nodiscard]] net::HttpResponse map_download(const net::HttpRequest& request, std::string_view query) const;
  [[nodiscard]] net::HttpResponse occupancy(const net::HttpRequest& request) const;
  [[nodiscard]] net::HttpResponse tile_index(const net::HttpRequest& request) const;
  [[nodiscard]] net::HttpResponse tile(const net::HttpRequest& request, std::string_view coordinates) const;
  [[nodiscard]] net::HttpResponse maps(const net::HttpRequest& request, std::string_view rest) const;
  // api/metrics_endpoint.cpp
  [[nodiscard]] net::HttpResponse metrics(const net::HttpRequest& request) const;

  const net::ServerServices& services_;
  const net::ClientHub& hub_;
  const streams::StatusStream& status_;
  const net::ServerMetrics& metrics_;
  std::string sim_world_;  // GET /api/v1/sim/world, encoded once; empty for a real robot
};

}  // namespace strata::api

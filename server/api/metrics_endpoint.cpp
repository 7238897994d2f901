// GET /metrics: counters and gauges in the Prometheus text exposition format (version 0.0.4).
#include <spdlog/fmt/fmt.h>

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/api/http_router.hpp"
#include "server/api/responses.hpp"

namespace strata::api {
namespace {

void metric(std::string& out, std::string_view name, std::string_view type, std::string_view help,
            double value) {
  out += fmt::format("# HELP {} {}\n# TYPE {} {}\n{} {}\n", name, help, name, type, name, value);
}

/// A gauge with one series per value of a label, 1 for the current value and 0 for the others: an alert
/// asks for `NAME{LABEL="value"} == 1`.
void one_hot(std::string& out, std::string_view name, std::string_view help, std::string_view label,
             std::initializer_list<std::string_view> values, std::string_view current) {
  out += fmt::format("# HELP {} {}\n# TYPE {} gauge\n", name, help, name);
  for (const std::string_view value : values)
    out += fmt::format("{}{{{}=\"{}\"}} {}\n", name, label, value, value == current ? 1 : 0);
}

/// One series per connected client, labelled with its number and role: how far behind it is.
void per_client(std::string& out, const std::vector<streams::ClientStats>& clients) {
  const auto series = [&](std::string_view name, std::string_view type, std::string_view help,
                          auto value_of) {
    out += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
    for (const auto& client : clients) {
      const std::optional<double> value = value_of(client);
      if (value) {
        out += fmt::format("{}{{client=\"{}\",role=\"{}\"}} {}\n", name, client.id,
                           client.operator_role ? "operator" : "viewer", *value);
      }
    }
  };
  series("strata_ws_client_queued_bytes", "gauge", "bytes waiting in the client's send queue",
         [](const auto& c) { return std::optional<double>(static_cast<double>(c.queued_bytes)); });
  series("strata_ws_client_socket_bytes", "gauge",
         "bytes in the client's socket that it has not acknowledged yet",
         [](const auto& c) { return std::optional<double>(static_cast<double>(c.socket_bytes)); });
  series("strata_ws_client_superseded_total", "counter",
         "messages replaced by a newer one (a pose, a tile) before they could be written to the client",
         [](const auto& c) { return std::optional<double>(static_cast<double>(c.superseded)); });
  series("strata_ws_client_pose_age_seconds", "gauge",
         "age of the last pose written to the client, when its write completed",
         [](const auto& c) { return c.pose_age_s; });
}

}  // namespace

protocol::HttpResponse HttpRouter::metrics(const protocol::HttpRequest& request) const {
  const auto count = [](const std::atomic<std::uint64_t>& counter) {
    return static_cast<double>(counter.load(std::memory_order_relaxed));
  };
  std::string out;
  metric(out, "strata_http_requests_total", "counter", "HTTP requests received",
         count(metrics_.http_requests));
  metric(out, "strata_ws_clients", "gauge", "WebSocket clients connected now",
         static_cast<double>(hub_.size()));
  metric(out, "strata_ws_connections_total", "counter", "WebSocket connections accepted",
         count(metrics_.ws_connections));
  metric(out, "strata_ws_messages_received_total", "counter", "WebSocket messages received from clients",
         count(metrics_.ws_messages_in));
  metric(out, "strata_ws_errors_sent_total", "counter", "client messages refused with an error",
         count(metrics_.ws_errors_sent));
  metric(out, "strata_ws_rate_limited_total", "counter", "client messages refused for the rate limit",
         count(metrics_.ws_rate_limited));
  metric(out, "strata_ws_stale_teleop_total", "counter",
         "teleop commands that would have moved the robot, refused as stale or out of order",
         count(metrics_.ws_stale_teleop));
  metric(out, "strata_ws_slow_clients_dropped_total", "counter",
         "clients disconnected for not keeping up: a write stalled, too many replies unread, or silent "
         "(no answer to the ping)",
         count(metrics_.ws_slow_dropped));
  metric(out, "strata_ws_bytes_sent_total", "counter", "payload bytes sent to WebSocket clients",
         count(metrics_.ws_bytes_out));
  metric(out, "strata_auth_failures_total", "counter", "requests that offered a wrong operator token",
         count(metrics_.auth_failures));
  metric(out, "strata_ws_refused_origin_total", "counter",
         "WebSocket upgrades refused: a browser page from an origin not allowed",
         count(metrics_.ws_refused_origin));
  metric(out, "strata_ws_refused_full_total", "counter",
         "WebSocket upgrades refused: the WebSocket client limit was reached",
         count(metrics_.ws_refused_full));
  metric(out, "strata_http_refused_full_total", "counter",
         "connections refused with 503: the HTTP connection limit was reached",
         count(metrics_.http_refused_full));
  metric(out, "strata_refused_address_total", "counter",
         "connections refused with 503: their address held max-connections-per-address already",
         count(metrics_.refused_address));
  per_client(out, hub_.stats());
  metric(out, "strata_http_refused_host_total", "counter",
         "requests refused: a Host header that is not this server's (DNS rebinding)",
         count(metrics_.refused_host));

  const auto registration = services_.robot->registration();
  metric(out, "strata_scans_total", "counter", "scans the localizer processed",
         static_cast<double>(registration.scans));
  metric(out, "strata_registrations_accepted_total", "counter", "registrations fault control accepted",
         static_cast<double>(registration.accepted));
  metric(out, "strata_registrations_rejected_total", "counter", "registrations fault control rejected",
         static_cast<double>(registration.rejected));
  metric(out, "strata_registrations_kept_odometry_total", "counter",
         "registrations not used at all: the odometry guess was kept",
         static_cast<double>(registration.kept_odometry));
  metric(out, "strata_pose_graph_loops", "gauge", "loop closures in the pose graph",
         static_cast<double>(registration.graph.loops));
  metric(out, "strata_pose_graph_keyframes", "gauge", "keyframes in the pose graph",
         static_cast<double>(registration.graph.keyframes));
  using enum LocalizationState;
  one_hot(out, "strata_localization_state", "how far the pose can be trusted now: ok, degraded or lost",
          "state", {to_string(kOk), to_string(kDegraded), to_string(kLost)},
          to_string(registration.localization.state));
  metric(out, "strata_scans_dropped_total", "counter", "scans skipped because the localizer was busy",
         static_cast<double>(registration.dropped));
  const nlohmann::json status = status_.fields();
  metric(out, "strata_scan_rate_hz", "gauge", "scans registered per second (10 s average)",
         status["scan_rate"].get<double>());
  const auto& map = status["map"];
  metric(out, "strata_map_version", "gauge", "map version (increments with every inserted scan)",
         map["version"].get<double>());
  metric(out, "strata_map_tiles", "gauge", "MLS map tiles", map["tiles"].get<double>());
  metric(out, "strata_map_cells", "gauge", "MLS map cells with patches", map["cells"].get<double>());
  metric(out, "strata_map_patches", "gauge", "MLS map patches", map["patches"].get<double>());
  metric(out, "strata_map_bytes", "gauge", "MLS map memory, bytes", map["bytes"].get<double>());
  metric(out, "strata_map_rebuilds_total", "counter",
         "maps rebuilt from the keyframes a pose graph optimization moved", map["rebuilds"].get<double>());

  auto response =
      make_response(request, protocol::http::status::ok, std::move(out), "text/plain; version=0.0.4");
  response.set(protocol::http::field::cache_control, "no-store");
  return response;
}

}  // namespace strata::api

#pragma once

#include <filesystem>
#include <string>

#include "server/net/client_hub.hpp"
#include "server/net/http_types.hpp"
#include "server/state/robot_state.hpp"

namespace strata::api {

/// Answers every plain HTTP request: REST under /api/v1, /healthz, and the web app's static files.
/// Pure request-in, response-out; the session owns the socket.
class HttpRouter {
 public:
  /// `sim_world` is the body of GET /api/v1/sim/world, empty when the robot is not simulated.
  HttpRouter(const RobotState& robot, const net::ClientHub& hub, std::filesystem::path web_root,
             std::string sim_world);

  [[nodiscard]] net::HttpResponse handle(const net::HttpRequest& request) const;

 private:
  [[nodiscard]] net::HttpResponse serve_static(const net::HttpRequest& request, std::string_view path) const;

  const RobotState& robot_;
  const net::ClientHub& hub_;
  std::filesystem::path web_root_;
  std::string sim_world_;
};

}  // namespace strata::api

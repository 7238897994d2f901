#pragma once

#include <filesystem>
#include <string>

#include "drivers/sim/world/world.hpp"
#include "server/api/http_router.hpp"
#include "server/net/client_hub.hpp"
#include "server/protocol/messages.hpp"
#include "server/state/robot_state.hpp"

namespace strata::net {

/// What every session shares: the robot's state, the connected clients and the request router.
struct ServerContext {
  /// `sim_world` is the simulated world, or nullptr for a real robot.
  ServerContext(const RobotState& robot_state, std::filesystem::path web_root, const sim::World* sim_world)
      : robot(robot_state),
        sim_world_message(sim_world ? protocol::sim_world_message(*sim_world) : std::string()),
        router(robot_state, hub, std::move(web_root),
               sim_world ? protocol::sim_world(*sim_world).dump() : std::string()) {}

  const RobotState& robot;
  std::string sim_world_message;  ///< sent to every client on connect; empty for a real robot
  ClientHub hub;
  api::HttpRouter router;
};

}  // namespace strata::net

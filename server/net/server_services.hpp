#pragma once

#include <filesystem>
#include <string>

#include "drivers/sim/world/world.hpp"
#include "server/control/robot_commands.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata::net {

/// The parts of the running robot the network side reaches: state to read and commands to give. Any
/// pointer may be null (a unit test, a server without a navigator); the features that need it answer
/// `unavailable`.
struct ServerServices {
  const RobotState* robot = nullptr;
  const MapState* map = nullptr;
  MotionCommands* motion = nullptr;
  MapCommands* maps = nullptr;
  const sim::World* sim_world = nullptr;  ///< the simulated world, or null for a real robot
  std::string operator_token;             ///< empty: nobody is an operator
  std::filesystem::path web_root;
};

}  // namespace strata::net

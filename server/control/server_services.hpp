#pragma once

#include "server/control/network_options.hpp"
#include "server/control/robot_commands.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata {

namespace sim {
class World;
}  // namespace sim

/// The parts of the running robot the network side reaches: state to read and commands to give, and how
/// it meets its clients. Any pointer may be null (a unit test, a server without a navigator); the features
/// that need it answer `unavailable`.
struct ServerServices {
  const RobotState* robot = nullptr;
  const MapState* map = nullptr;
  MotionCommands* motion = nullptr;
  MapCommands* maps = nullptr;
  LocalizationCommands* localization = nullptr;
  CalibrationCommands* calibration = nullptr;
  const sim::World* sim_world = nullptr;  ///< the simulated world, or null for a real robot
  /// As the server runs with them: the operator token made if none was given (empty here: nobody is an
  /// operator), the web root found, the allowed hosts with the machine's own names added.
  NetworkOptions network;
};

}  // namespace strata

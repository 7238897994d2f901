#pragma once

#include <filesystem>
#include <string>

namespace strata {

/// The robot in a fleet: VDA 5050 2.1 over MQTT (docs/fleet.md). An option is a field here, a line in
/// server/app/serve_command.cpp and a key in deploy/strata.example.ini.
struct FleetOptions {
  std::string broker;                   ///< mqtt://HOST:PORT or mqtts://HOST:PORT; empty: no fleet link
  std::string manufacturer = "Strata";  ///< the topics' and headers' manufacturer
  std::string serial_number;            ///< the topics' and headers' serialNumber; empty: the host name
  std::string interface_name = "uagv";  ///< the topics' first level
  std::string username;                 ///< empty: none
  std::string password;                 ///< with username
  std::filesystem::path ca_file;        ///< mqtts: the broker's CA (PEM); empty: the system's CAs
  // The factsheet's physical facts, filled from the robot's options at start.
  double robot_radius = 0.45;  ///< m
  double robot_height = 1.0;   ///< m
  double max_speed = 1.0;      ///< m/s
};

}  // namespace strata

#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"

namespace strata::app {

/// The robot's body and what it can climb: what the drivable map and the planner assume.
/// Defaults: the thesis's wheelchair.
struct RobotParameters {
  double radius = 0.45;         ///< m; the planner keeps the robot's centre this far from edges
  double height = 1.0;          ///< m; free space needed above a surface to drive there
  double max_step = 0.08;       ///< m; highest step between neighbouring cells
  double max_slope_deg = 15.0;  ///< steepest drivable ground
};

/// Playing a dataset instead of simulating (strata serve --replay DIR).
struct ReplayParameters {
  std::filesystem::path directory;  ///< empty: the simulator
  std::string rate =
      "recorded";  ///< "recorded" (at --time-scale) or "max" (as fast as the pipeline takes it)
  std::string odometry = "auto";    ///< "auto", "dataset" or "reference" (with the noise below)
  double noise_translation = 0.0;   ///< m per m driven, 1-sigma, for odometry made from reference poses
  double noise_rotation_deg = 0.0;  ///< degrees of heading per m driven, 1-sigma
};

/// A lidar instead of the simulator: a packet capture played (--pcap FILE --lidar MODEL) or the live sensor
/// (--lidar MODEL alone). Pacing of a capture: ReplayParameters::rate and ServeOptions::time_scale.
struct LidarParameters {
  std::string model;                  ///< vlp16, hdl32e, os1; empty: no lidar
  std::filesystem::path pcap;         ///< empty: live UDP
  std::filesystem::path calibration;  ///< Velodyne YAML (optional), Ouster metadata JSON (required)
  std::uint16_t port = 0;             ///< live UDP port; 0: the model's (2368 Velodyne, 7502 Ouster)
  std::string address = "0.0.0.0";    ///< live: the address to receive on
  std::string mount = "0,0,0";        ///< x,y,z[,roll,pitch,yaw] of the sensor on the base, m and degrees
  bool keep_partial = false;          ///< also hand on partial revolutions (stream ends, dropped packets)
};

struct ServeOptions {
  std::string bind_address = "0.0.0.0";
  std::uint16_t port = 8080;
  std::filesystem::path web_root;  ///< empty: the bundle next to the executable
  double pose_rate = 25.0;         ///< Hz
  std::uint64_t seed = 1;
  double time_scale = 1.0;
  std::string world = "campus";     ///< a built-in world's name or a world file's path
  std::string scanner = "tilting";  ///< tilting (stop-and-go, the thesis robot), lidar, none
  int io_threads = 2;
  /// The operator token (goals, teleop, save, load). Empty: a random one is made and printed at start.
  std::string operator_token;
  std::filesystem::path maps_dir;  ///< saved maps; empty: default_maps_dir()
  /// TLS: a PEM certificate (chain) and its unencrypted PEM key, both or neither. With them the port
  /// serves https:// and wss:// only and refuses plain HTTP.
  std::filesystem::path tls_certificate;
  std::filesystem::path tls_key;
  /// Browser origins besides the server's own that may open the WebSocket ("*": any); pages elsewhere
  /// are refused with 403, clients without an Origin header (scripts) are not affected.
  std::vector<std::string> allowed_origins;
  std::size_t max_clients = 256;  ///< WebSocket clients at once; one more is refused with 503
  /// Other TCP connections at once (HTTP, idle keep-alive); one more is answered 503 and closed.
  std::size_t max_http_connections = 512;
  /// Host names requests may name besides IP literals, localhost and this machine's name ("*": any);
  /// others are refused with 403 (DNS rebinding).
  std::vector<std::string> allowed_hosts;
  RobotParameters robot;
  ReplayParameters replay;
  LidarParameters lidar;
  std::filesystem::path record;  ///< write the scans and odometry here (replay layout); empty: no recording
  std::size_t max_scans = 0;     ///< hand at most this many scans to the pipeline; 0: all
  /// Wall-clock seconds a due scan may be waited for before the status says the sensor stalled; 0: 10 s,
  /// longer when --time-scale slows the simulator down.
  double sensor_timeout = 0.0;
  /// A fault drill with the simulator: "START,DURATION", simulated seconds from the start during which
  /// the sensor delivers nothing; empty: none.
  std::string sim_sensor_outage;
};

/// The token in a file, without surrounding whitespace; throws when the file cannot be read.
[[nodiscard]] std::string read_token_file(const std::filesystem::path& path);

/// Runs the server with the simulated robot or a replay until SIGINT or SIGTERM. Returns the process exit
/// code.
int serve(const ServeOptions& options);

/// A built-in world by name, or a world file by path; throws with the choices when neither exists.
[[nodiscard]] sim::WorldDescription load_world(const std::string& name_or_path);
[[nodiscard]] sim::ScannerKind parse_scanner(const std::string& name);

/// Where saved maps live when no --maps-dir is given: $XDG_DATA_HOME/strata/maps, else
/// ~/.local/share/strata/maps (the XDG default), else ./maps when there is no HOME either.
[[nodiscard]] std::filesystem::path default_maps_dir();

/// Where the web bundle is when none is given: `web/` next to the executable (a build tree), or
/// `../share/strata/web` from it (an installed package).
[[nodiscard]] std::filesystem::path default_web_root();

}  // namespace strata::app

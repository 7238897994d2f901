// `strata serve`: its options, read from the command line or a config file.
#include "server/app/serve_command.hpp"

#include <map>
#include <string>
#include <vector>

#include "server/auth/host_policy.hpp"
#include "server/auth/request_auth.hpp"

namespace strata::app {
namespace {

/// An option whose value is one of `names`: help and errors list the names, the default is shown by name,
/// and the option struct holds the enum.
template <class Enum>
void add_choice(CLI::App* command, const std::string& flag, Enum& value,
                const std::map<std::string, Enum>& names, const std::string& help) {
  std::vector<std::string> choices;
  for (const auto& [name, known] : names)
    choices.push_back(name);
  command
      ->add_option_function<std::string>(
          flag, [&value, &names](const std::string& name) { value = names.at(name); }, help)
      ->check(CLI::IsMember(choices))
      ->default_str(name_of(names, value));
}

}  // namespace

CLI::App* add_serve_command(CLI::App& app, ServeOptions& options) {
  auto* command = app.add_subcommand(
      "serve",
      "Run the server: web app, REST API under /api/v1 and WebSocket at /ws, with the simulated robot or a "
      "replayed dataset");
  command->add_option("-p,--port", options.network.port, "TCP port to listen on (0 picks a free one)")
      ->capture_default_str();
  command
      ->add_option("--bind", options.network.bind_address,
                   "Address to listen on (127.0.0.1 for this machine only)")
      ->capture_default_str();
  command->add_option("--web-root", options.network.web_root,
                      "Directory of the built web app (default: the bundle installed with strata)");
  command->add_option("--pose-rate", options.network.pose_rate, "Pose stream rate to clients, Hz")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  command->add_option("--seed", options.seed, "Simulator random seed (same seed, same run)")
      ->capture_default_str();
  command->add_option("--time-scale", options.time_scale, "Simulated seconds per real second")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 100.0));
  command
      ->add_option("--world", options.world,
                   "Simulated world: a built-in name (campus, yard) or a world file (JSON, see "
                   "drivers/sim/worlds/README.md)")
      ->capture_default_str();
  add_choice(command, "--scanner", options.scanner, kScannerNames,
             "Simulated 3D sensor: tilting (the thesis robot's rotating laser, stop-and-go), lidar "
             "(VLP-16-like, scans while driving), none");
  command->add_option("--maps-dir", options.maps_dir,
                      "Directory of saved maps, created if missing (default: $XDG_DATA_HOME/strata/maps, "
                      "i.e. ~/.local/share/strata/maps)");
  command->add_option("--imu-calibration", options.imu_calibration,
                      "File the base IMU's calibration is kept in between runs (default: "
                      "$XDG_STATE_HOME/strata/imu-calibration.json, i.e. ~/.local/state/strata/...)");
  command->add_flag("!--no-imu-calibration", options.keep_imu_calibration,
                    "Neither start from a kept IMU calibration nor keep this run's");
  command->add_option(
      "--map", options.map,
      "A saved map (its name in --maps-dir) to start with, for --mode: mapping goes on in it, "
      "or the robot localizes in it and it is not changed");
  command
      ->add_option_function<std::string>(
          "--mode",
          [&options](const std::string& text) {
            options.map_mode = map_mode_from_string(text).value_or(MapMode::kMapping);
          },
          "What --map is for: mapping (default) or localize")
      ->check(CLI::IsMember({"mapping", "localize"}));
  command->add_option("--io-threads", options.network.io_threads, "Threads serving network clients")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  command
      ->add_option(
          "--operator-token", options.network.operator_token,
          "Operator token for goals, teleop, save and load (16-128 characters of A-Z a-z 0-9 - _). "
          "Prefer the config file or STRATA_OPERATOR_TOKEN: a command line is visible to other users. "
          "Default: a random token, printed at start")
      ->envname("STRATA_OPERATOR_TOKEN");
  command->add_option("--robot-radius", options.robot.radius, "Robot radius the planner keeps from edges, m")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 5.0));
  command
      ->add_option("--robot-height", options.robot.height, "Free space the robot needs above the ground, m")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 5.0));
  command->add_option("--max-step", options.robot.max_step, "Highest step the robot drives over, m")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option("--max-slope", options.robot.max_slope_deg, "Steepest ground the robot drives on, degrees")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 60.0));
  command
      ->add_option(
          "--replay", options.replay.directory,
          "Replay a dataset instead of simulating: a Strata recording (--record, or a FILE.mcap from "
          "--record-mcap), 3DTK scanNNN.3d + .pose, KITTI velodyne/*.bin + poses.txt, or scans.csv "
          "listing PCD/PLY files")
      ->check(CLI::ExistingPath);
  add_choice(command, "--replay-rate", options.replay.rate, kReplayRateNames,
             "recorded: at the dataset's clock times --time-scale; max: as fast as the pipeline takes the "
             "scans (none dropped)");
  add_choice(command, "--replay-odometry", options.replay.odometry, kOdometrySourceNames,
             "Replay odometry: dataset (its odometry), reference (made from its reference poses, with "
             "--replay-noise-*), none (the scans alone, as a lidar without wheels: the motion is predicted "
             "from the scans), auto (dataset if it has odometry, else reference, else none)");
  command
      ->add_option(
          "--replay-noise-translation", options.replay.noise_translation,
          "Odometry from reference poses: translation error per metre driven, 1-sigma (seeded by --seed)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option("--replay-noise-rotation", options.replay.noise_rotation_deg,
                   "Odometry from reference poses: heading error per metre driven, degrees, 1-sigma")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 90.0));
  command
      ->add_option("--pcap", options.lidar.pcap,
                   "Play a lidar packet capture (classic pcap) instead of simulating; needs --lidar MODEL; "
                   "paced by --replay-rate and --time-scale")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--lidar,--lidar-model", options.lidar.model,
                   "Lidar model: vlp16, hdl32e, os1. With --pcap, the capture's sensor; alone, listen to the "
                   "live sensor's UDP packets instead of simulating")
      ->check(CLI::IsMember({"vlp16", "hdl32e", "hdl32", "os1", "os1-64"}));
  command->add_option("--lidar-calibration", options.lidar.calibration,
                      "Velodyne calibration YAML (optional: the datasheet's angles), Ouster metadata JSON "
                      "(required for os1)");
  command
      ->add_option("--lidar-port", options.lidar.port,
                   "Live lidar: UDP port of its point data (0: the model's, 2368 Velodyne, 7502 Ouster)")
      ->capture_default_str();
  command
      ->add_option("--lidar-address", options.lidar.address, "Live lidar: address to receive its packets on")
      ->capture_default_str();
  command->add_option(
      "--lidar-mount", options.lidar.mount,
      "The lidar on the robot: x,y,z[,roll,pitch,yaw] in m and degrees (z: its height above the "
      "ground, which the map needs below it). Default: estimated from the ground under the sensor "
      "in the first scans (logged); 0,0,0 keeps the sensor's frame as the base's. Also for "
      "--replay: replaces the dataset's mount");
  command->add_option("--record", options.record,
                      "Record the scans and odometry the pipeline receives into this directory (replay "
                      "layout), to replay the run later with --replay");
  command->add_option("--record-mcap", options.record_mcap,
                      "Record the run into this MCAP file of ROS 2 messages (scans, odometry, IMU, pose, tf, "
                      "path, goal events, the drivable map; docs/interop.md), written as FILE.part until a "
                      "clean stop; replay it with --replay FILE");
  command->add_flag("--record-mcap-uncompressed", options.record_mcap_uncompressed,
                    "--record-mcap without zstd compression");
  command
      ->add_option("--max-scans", options.max_scans,
                   "Hand at most this many scans to the pipeline, then keep serving the map (0: all)")
      ->capture_default_str();
  command
      ->add_option("--sensor-timeout", options.sensor_timeout,
                   "Seconds a due scan may be late before the status reports the sensor stalled (0: 10 s, "
                   "longer when --time-scale is below 1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  command->add_option(
      "--sim-sensor-outage", options.sim_sensor_outage,
      "Fault drill with the simulator: START,DURATION in simulated seconds from the start during "
      "which the sensor delivers no scans (the status reports it stalled, then recovered)");
  command
      ->add_flag("--sim-imu,!--no-sim-imu", options.sim_imu,
                 "The simulated base's IMU: its gyro turns the wheel odometry and its accelerometer reports "
                 "gravity with each scan, which holds the map's tilt and height. --no-sim-imu: wheels alone")
      ->capture_default_str();
  command
      ->add_option(
          "--tls-cert", options.network.tls_certificate,
          "TLS certificate (PEM, may hold the chain): serve https:// and wss:// on the port and refuse "
          "plain HTTP. Needs --tls-key")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--tls-key", options.network.tls_key,
                   "The TLS certificate's private key (PEM, unencrypted)")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--allowed-origins", options.network.allowed_origins,
                   "Browser origins (scheme://host[:port]) that may open the WebSocket besides this "
                   "server's own web app, e.g. a kiosk page served elsewhere; * allows any. Pages from "
                   "other origins are refused (403); scripts, which send no Origin, are not affected")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& origin) {
            return auth::is_valid_origin_pattern(origin)
                       ? std::string()
                       : "'" + origin + "' is not an origin (http://host[:port], https://host[:port], *)";
          },
          "ORIGIN"));
  command
      ->add_option("--max-clients", options.network.max_clients,
                   "WebSocket clients at once; one more is refused with HTTP 503 until one leaves")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command
      ->add_option("--max-http-connections", options.network.max_http_connections,
                   "TCP connections at once that are not WebSocket clients (HTTP requests, idle keep-alive); "
                   "one more is answered HTTP 503 and closed")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command
      ->add_option("--max-connections-per-address", options.network.max_connections_per_address,
                   "Connections of every kind (HTTP, WebSocket) at once from one IP address; one more is "
                   "answered HTTP 503 and closed, so one host cannot lock the others out")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command
      ->add_option("--client-timeout", options.network.client_timeout_s,
                   "Seconds a WebSocket client may stay silent before it is dropped: the server pings it "
                   "after half of this, and a client that neither answers nor sends is gone or not reading")
      ->capture_default_str()
      ->check(CLI::Range(2.0, 3600.0));
  command
      ->add_option("--allowed-hosts", options.network.allowed_hosts,
                   "Host names requests may be addressed to besides IP addresses, localhost and this "
                   "machine's name (and name.local), e.g. a DNS name of the robot; * allows any. Requests "
                   "naming another host are refused (403): against DNS rebinding")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& host) {
            return auth::is_valid_host_pattern(host)
                       ? std::string()
                       : "'" + host + "' is not a host name (letters, digits, '-', '.'; or *)";
          },
          "HOST"));
  command->add_flag("--lidar-keep-partial", options.lidar.keep_partial,
                    "Also hand on partial lidar revolutions (the ends of a capture, after dropped packets): "
                    "for captures shorter than two revolutions");
  command
      ->add_option("--operator-token-file", options.network.operator_token_file,
                   "Read the operator token from this file")
      ->check(CLI::ExistingFile);
  command->add_option("--vda5050", options.network.fleet.broker,
                      "Join a fleet: VDA 5050 2.1 over MQTT to this broker, mqtt://HOST[:PORT] or "
                      "mqtts://HOST[:PORT] (docs/fleet.md)");
  command
      ->add_option("--vda5050-manufacturer", options.network.fleet.manufacturer,
                   "VDA 5050: the manufacturer in the topics and headers")
      ->capture_default_str();
  command->add_option(
      "--vda5050-serial", options.network.fleet.serial_number,
      "VDA 5050: the vehicle's serialNumber in the topics and headers (default: the host name)");
  command
      ->add_option("--vda5050-interface", options.network.fleet.interface_name,
                   "VDA 5050: the topics' interface name, <interface>/v2/<manufacturer>/<serial>/<topic>")
      ->capture_default_str();
  command->add_option("--vda5050-username", options.network.fleet.username,
                      "VDA 5050: the broker's user name");
  command
      ->add_option("--vda5050-password", options.network.fleet.password,
                   "VDA 5050: the broker user's password (prefer the config file or STRATA_VDA5050_PASSWORD)")
      ->envname("STRATA_VDA5050_PASSWORD");
  command
      ->add_option("--vda5050-ca-file", options.network.fleet.ca_file,
                   "VDA 5050 over mqtts://: the broker's CA certificate (PEM); default: the system's CAs")
      ->check(CLI::ExistingFile);
  command->fallthrough();  // `strata serve --config FILE` works as well as `strata --config FILE serve`
  return command;
}

}  // namespace strata::app

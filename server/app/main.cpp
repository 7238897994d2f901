// strata: the map server's command line. Each subcommand is one job a user or a script runs.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "server/protocol/build_info.hpp"
#include "server/app/map_command.hpp"
#include "server/app/plan_command.hpp"
#include "server/app/register_command.hpp"
#include "server/app/serve.hpp"
#include "server/auth/host_policy.hpp"
#include "server/auth/operator_token.hpp"
#include "server/auth/request_auth.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Strata: a map server for mobile robots on uneven, multi-level ground.\n"
      "Registers 3D scans, builds a Multi-Level Surface map, plans and drives to goals, and serves\n"
      "it all to a browser and to scripts over HTTP and WebSocket.",
      "strata"};
  app.require_subcommand(1);
  app.set_version_flag("--version", strata::build_info::version());
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "Log verbosity: trace, debug, info, warn, error, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));

  strata::app::ServeOptions serve;
  auto* serve_cmd = app.add_subcommand(
      "serve",
      "Run the server: web app, REST API under /api/v1 and WebSocket at /ws, with the simulated robot or a "
      "replayed dataset");
  serve_cmd->add_option("-p,--port", serve.port, "TCP port to listen on (0 picks a free one)")
      ->capture_default_str();
  serve_cmd
      ->add_option("--bind", serve.bind_address, "Address to listen on (127.0.0.1 for this machine only)")
      ->capture_default_str();
  serve_cmd->add_option("--web-root", serve.web_root,
                        "Directory of the built web app (default: the bundle installed with strata)");
  serve_cmd->add_option("--pose-rate", serve.pose_rate, "Pose stream rate to clients, Hz")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  serve_cmd->add_option("--seed", serve.seed, "Simulator random seed (same seed, same run)")
      ->capture_default_str();
  serve_cmd->add_option("--time-scale", serve.time_scale, "Simulated seconds per real second")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 100.0));
  serve_cmd
      ->add_option("--world", serve.world,
                   "Simulated world: a built-in name (campus, yard) or a world file (JSON, see "
                   "drivers/sim/worlds/README.md)")
      ->capture_default_str();
  serve_cmd
      ->add_option("--scanner", serve.scanner,
                   "Simulated 3D sensor: tilting (the thesis robot's rotating laser, stop-and-go), lidar "
                   "(VLP-16-like, scans while driving), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"tilting", "lidar", "none"}));
  serve_cmd->add_option("--maps-dir", serve.maps_dir,
                        "Directory of saved maps, created if missing (default: $XDG_DATA_HOME/strata/maps, "
                        "i.e. ~/.local/share/strata/maps)");
  serve_cmd->add_option("--io-threads", serve.io_threads, "Threads serving network clients")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  serve_cmd
      ->add_option(
          "--operator-token", serve.operator_token,
          "Operator token for goals, teleop, save and load (16-128 characters of A-Z a-z 0-9 - _). "
          "Prefer the config file or STRATA_OPERATOR_TOKEN: a command line is visible to other users. "
          "Default: a random token, printed at start")
      ->envname("STRATA_OPERATOR_TOKEN");
  serve_cmd->add_option("--robot-radius", serve.robot.radius, "Robot radius the planner keeps from edges, m")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 5.0));
  serve_cmd
      ->add_option("--robot-height", serve.robot.height, "Free space the robot needs above the ground, m")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 5.0));
  serve_cmd->add_option("--max-step", serve.robot.max_step, "Highest step the robot drives over, m")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  serve_cmd
      ->add_option("--max-slope", serve.robot.max_slope_deg, "Steepest ground the robot drives on, degrees")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 60.0));
  serve_cmd
      ->add_option("--replay", serve.replay.directory,
                   "Replay a dataset instead of simulating: a Strata recording (--record), 3DTK scanNNN.3d + "
                   ".pose, KITTI velodyne/*.bin + poses.txt, or scans.csv listing PCD/PLY files")
      ->check(CLI::ExistingDirectory);
  serve_cmd
      ->add_option(
          "--replay-rate", serve.replay.rate,
          "recorded: at the dataset's clock times --time-scale; max: as fast as the pipeline takes the "
          "scans (none dropped)")
      ->capture_default_str()
      ->check(CLI::IsMember({"recorded", "max"}));
  serve_cmd
      ->add_option("--replay-odometry", serve.replay.odometry,
                   "Replay odometry: dataset (its odometry), reference (made from its reference poses, with "
                   "--replay-noise-*), auto (dataset if it has odometry)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "dataset", "reference"}));
  serve_cmd
      ->add_option(
          "--replay-noise-translation", serve.replay.noise_translation,
          "Odometry from reference poses: translation error per metre driven, 1-sigma (seeded by --seed)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  serve_cmd
      ->add_option("--replay-noise-rotation", serve.replay.noise_rotation_deg,
                   "Odometry from reference poses: heading error per metre driven, degrees, 1-sigma")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 90.0));
  serve_cmd
      ->add_option("--pcap", serve.lidar.pcap,
                   "Play a lidar packet capture (classic pcap) instead of simulating; needs --lidar MODEL; "
                   "paced by --replay-rate and --time-scale")
      ->check(CLI::ExistingFile);
  serve_cmd
      ->add_option("--lidar,--lidar-model", serve.lidar.model,
                   "Lidar model: vlp16, hdl32e, os1. With --pcap, the capture's sensor; alone, listen to the "
                   "live sensor's UDP packets instead of simulating")
      ->check(CLI::IsMember({"vlp16", "hdl32e", "hdl32", "os1", "os1-64"}));
  serve_cmd->add_option("--lidar-calibration", serve.lidar.calibration,
                        "Velodyne calibration YAML (optional: the datasheet's angles), Ouster metadata JSON "
                        "(required for os1)");
  serve_cmd
      ->add_option("--lidar-port", serve.lidar.port,
                   "Live lidar: UDP port of its point data (0: the model's, 2368 Velodyne, 7502 Ouster)")
      ->capture_default_str();
  serve_cmd
      ->add_option("--lidar-address", serve.lidar.address, "Live lidar: address to receive its packets on")
      ->capture_default_str();
  serve_cmd
      ->add_option("--lidar-mount", serve.lidar.mount,
                   "The lidar on the robot: x,y,z[,roll,pitch,yaw] in m and degrees (z: its height above the "
                   "ground, which the map needs below it)")
      ->capture_default_str();
  serve_cmd->add_option("--record", serve.record,
                        "Record the scans and odometry the pipeline receives into this directory (replay "
                        "layout), to replay the run later with --replay");
  serve_cmd
      ->add_option("--max-scans", serve.max_scans,
                   "Hand at most this many scans to the pipeline, then keep serving the map (0: all)")
      ->capture_default_str();
  serve_cmd
      ->add_option("--sensor-timeout", serve.sensor_timeout,
                   "Seconds a due scan may be late before the status reports the sensor stalled (0: 10 s, "
                   "longer when --time-scale is below 1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  serve_cmd->add_option(
      "--sim-sensor-outage", serve.sim_sensor_outage,
      "Fault drill with the simulator: START,DURATION in simulated seconds from the start during "
      "which the sensor delivers no scans (the status reports it stalled, then recovered)");
  serve_cmd
      ->add_option(
          "--tls-cert", serve.tls_certificate,
          "TLS certificate (PEM, may hold the chain): serve https:// and wss:// on the port and refuse "
          "plain HTTP. Needs --tls-key")
      ->check(CLI::ExistingFile);
  serve_cmd->add_option("--tls-key", serve.tls_key, "The TLS certificate's private key (PEM, unencrypted)")
      ->check(CLI::ExistingFile);
  serve_cmd
      ->add_option("--allowed-origins", serve.allowed_origins,
                   "Browser origins (scheme://host[:port]) that may open the WebSocket besides this "
                   "server's own web app, e.g. a kiosk page served elsewhere; * allows any. Pages from "
                   "other origins are refused (403); scripts, which send no Origin, are not affected")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& origin) {
            return strata::auth::is_valid_origin_pattern(origin)
                       ? std::string()
                       : "'" + origin + "' is not an origin (http://host[:port], https://host[:port], *)";
          },
          "ORIGIN"));
  serve_cmd
      ->add_option("--max-clients", serve.max_clients,
                   "WebSocket clients at once; one more is refused with HTTP 503 until one leaves")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  serve_cmd
      ->add_option("--max-http-connections", serve.max_http_connections,
                   "TCP connections at once that are not WebSocket clients (HTTP requests, idle keep-alive); "
                   "one more is answered HTTP 503 and closed")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  serve_cmd
      ->add_option("--allowed-hosts", serve.allowed_hosts,
                   "Host names requests may be addressed to besides IP addresses, localhost and this "
                   "machine's name (and name.local), e.g. a DNS name of the robot; * allows any. Requests "
                   "naming another host are refused (403): against DNS rebinding")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& host) {
            return strata::auth::is_valid_host_pattern(host)
                       ? std::string()
                       : "'" + host + "' is not a host name (letters, digits, '-', '.'; or *)";
          },
          "HOST"));
  serve_cmd->add_flag(
      "--lidar-keep-partial", serve.lidar.keep_partial,
      "Also hand on partial lidar revolutions (the ends of a capture, after dropped packets): "
      "for captures shorter than two revolutions");
  std::string token_file;
  serve_cmd->add_option("--operator-token-file", token_file, "Read the operator token from this file")
      ->check(CLI::ExistingFile);
  // Every serve option can also come from a config file: `strata serve --config strata.ini`, with the options
  // by their long names under a [serve] section (deploy/strata.example.ini). The command line wins.
  app.set_config("--config", "", "Read options from this file (INI/TOML; see deploy/strata.example.ini)");
  // A key no option has is refused at start, not ignored: a misspelt `max-client` would otherwise leave the
  // robot on the default without a word.
  app.allow_config_extras(CLI::config_extras_mode::error);
  serve_cmd->fallthrough();  // `strata serve --config FILE` works as well as `strata --config FILE serve`

  strata::app::RegisterOptions register_options;
  auto* register_cmd = strata::app::add_register_command(app, register_options);

  strata::app::MapBuildOptions map_build;
  strata::app::MapExportOptions map_export;
  const strata::app::MapCommand map_cmd = strata::app::add_map_command(app, map_build, map_export);
  strata::app::PlanOptions plan_options;
  auto* plan_cmd = strata::app::add_plan_command(app, plan_options);

  auto* version_cmd =
      app.add_subcommand("version", "Print the version and the libraries Strata was built with");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ConfigError& e) {
    // CLI11 says "INI was not able to parse serve.max-client"; say what that means and where to look.
    std::cerr << "strata: config file: " << e.what()
              << " (no option of that name; the keys are the long options of `strata serve --help`, under "
                 "[serve])\n";
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  // Logs go to stderr; stdout carries only what scripts read (the "serving on" line, command output).
  spdlog::set_default_logger(spdlog::stderr_color_mt("strata"));
  spdlog::set_level(spdlog::level::from_str(log_level));

  try {
    if (*serve_cmd) {
      if (!token_file.empty())
        serve.operator_token = strata::app::read_token_file(token_file);
      if (!serve.operator_token.empty() && !strata::auth::is_valid_token(serve.operator_token)) {
        throw std::runtime_error(
            "the operator token must be 16-128 characters of A-Z a-z 0-9 - _ (it travels in headers and "
            "WebSocket subprotocols)");
      }
      return strata::app::serve(serve);
    }
    if (*register_cmd)
      return strata::app::run_register(register_options);
    if (*map_cmd.build)
      return strata::app::run_map_build(map_build);
    if (*map_cmd.export_)
      return strata::app::run_map_export(map_export);
    if (*plan_cmd)
      return strata::app::run_plan(plan_options);
    if (*version_cmd) {
      std::printf("strata %s\n%s\n", strata::build_info::version().c_str(),
                  strata::build_info::libraries().dump(2).c_str());
      return 0;
    }
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return 1;
  }
  return 0;
}

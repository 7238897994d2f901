#include "server/app/serve.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/strand.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "drivers/replay/recorder.hpp"
#include "drivers/robot_driver.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/protocol/build_info.hpp"
#include "server/app/drivers.hpp"
#include "server/auth/host_policy.hpp"
#include "server/auth/operator_token.hpp"
#include "server/net/listener.hpp"
#include "server/net/server_context.hpp"
#include "server/net/tls_context.hpp"
#include "server/pipeline/localizer_worker.hpp"
#include "server/pipeline/mapping_worker.hpp"
#include "server/pipeline/navigator.hpp"
#include "server/net/periodic_broadcast.hpp"
#include "server/protocol/client_messages.hpp"
#include "server/protocol/messages.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata::app {

std::filesystem::path default_web_root() {
  std::error_code error;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error)
    return "web";
  const auto beside = exe.parent_path() / "web";
  if (std::filesystem::exists(beside / "index.html", error))
    return beside;
  return exe.parent_path().parent_path() / "share" / "strata" / "web";
}

std::filesystem::path default_maps_dir() {
  const char* data_home = std::getenv("XDG_DATA_HOME");
  if (data_home != nullptr && *data_home == '/')  // XDG: a relative value is invalid and ignored
    return std::filesystem::path(data_home) / "strata" / "maps";
  const char* home = std::getenv("HOME");
  if (home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".local" / "share" / "strata" / "maps";
  return "maps";
}

sim::WorldDescription load_world(const std::string& name_or_path) {
  if (std::filesystem::exists(name_or_path))
    return sim::load_world_file(name_or_path);
  const auto names = sim::builtin_world_names();
  if (std::find(names.begin(), names.end(), name_or_path) != names.end())
    return sim::builtin_world(name_or_path);
  std::string known;
  for (const auto& name : names)
    known += (known.empty() ? "" : ", ") + name;
  throw std::runtime_error("no world file '" + name_or_path +
                           "' and no built-in world of that name (built-in: " + known + ")");
}

sim::ScannerKind parse_scanner(const std::string& name) {
  if (name == "tilting")
    return sim::ScannerKind::kTilting;
  if (name == "lidar")
    return sim::ScannerKind::kLidar;
  if (name == "none")
    return sim::ScannerKind::kNone;
  throw std::runtime_error("unknown scanner '" + name + "' (tilting, lidar, none)");
}

std::string read_token_file(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string token;
  if (!file || !std::getline(file, token))
    throw std::runtime_error("cannot read the operator token from " + path.string());
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ' || token.back() == '\t'))
    token.pop_back();
  return token;
}

int serve(const ServeOptions& options) {
  // A write past the file size limit (RLIMIT_FSIZE) then fails with EFBIG, so a map save reports io_error
  // and leaves the previous file, instead of the signal's default action killing the robot's server.
  std::signal(SIGXFSZ, SIG_IGN);
  // First, before anything starts: a bad certificate or key stops the server with the file's name.
  std::shared_ptr<boost::asio::ssl::context> tls;
  if (!options.tls_certificate.empty() || !options.tls_key.empty()) {
    if (options.tls_certificate.empty() || options.tls_key.empty())
      throw std::runtime_error("TLS needs both --tls-cert and --tls-key");
    tls = net::make_tls_context(options.tls_certificate, options.tls_key);
  }
  const std::filesystem::path web_root = options.web_root.empty() ? default_web_root() : options.web_root;
  if (!std::filesystem::exists(web_root / "index.html")) {
    spdlog::warn("no web app at {} (build it with the 'web' target); serving the API only",
                 web_root.string());
  }

  RobotState robot_state;
  // The simulator, or a dataset replayed: where odometry and scans come from.
  const std::unique_ptr<RobotDriver> driver = make_driver(options);
  const Eigen::Isometry3d map_from_odom = driver->initial_map_from_odom();
  robot_state.set_driver(DriverStatus{driver->kind(), false});
  // A stalled sensor: 10 s of wall time waiting for a due scan, stretched when --time-scale is below 1 (the
  // simulated scanner then takes longer per scan).
  robot_state.set_sensor_timeout(
      options.sensor_timeout > 0.0 ? options.sensor_timeout : 10.0 * std::max(1.0, 1.0 / options.time_scale));
  // --record: every sample and scan the pipeline receives, on the recorder's own thread.
  std::unique_ptr<replay::Recorder> recorder;
  if (!options.record.empty()) {
    const nlohmann::json metadata{{"source", driver->kind()},
                                  {"description", driver->description()},
                                  {"seed", options.seed},
                                  {"time_scale", options.time_scale},
                                  {"world", driver->world() != nullptr ? options.world : ""},
                                  {"scanner", driver->world() != nullptr ? options.scanner : ""},
                                  {"strata_version", build_info::version()}};
    recorder = std::make_unique<replay::Recorder>(options.record, metadata, map_from_odom);
  }
  // Declared first, destroyed last: the mapping thread (its map listener) and the robot's thread (its
  // command source) call into it.
  TraversabilityConfig traversability;
  traversability.max_step = options.robot.max_step;
  traversability.max_slope = options.robot.max_slope_deg * 3.14159265358979323846 / 180.0;
  traversability.robot_height = options.robot.height;
  pipeline::NavigatorConfig navigation;
  navigation.graph.traversability = traversability;
  navigation.graph.robot_radius = options.robot.radius;
  pipeline::Navigator navigator(navigation);
  // The live map (ARCHITECTURE.md 3, steps 6-8): the localizer hands on each registered scan. Declared
  // before the localizer, so it outlives the localizer's thread, which feeds it.
  MapState map_state;
  const std::filesystem::path maps_dir = options.maps_dir.empty() ? default_maps_dir() : options.maps_dir;
  pipeline::MappingOptions mapping_options;
  mapping_options.map.traversability = traversability;
  pipeline::MappingWorker mapping(map_state, maps_dir, mapping_options);
  MapCommands& map_commands = mapping;
  pipeline::LocalizerWorker localizer(robot_state, LocalizerOptions{}, map_from_odom);
  localizer.set_registered_scan_sink([&mapping](ScanEvent scan, const Eigen::Isometry3d& map_from_sensor) {
    mapping.submit(std::move(scan), map_from_sensor);
  });
  // Goals are planned on the live map: the navigator copies the map's surfaces after every change.
  mapping.add_listener(navigator.map_listener());
  // The navigator drives the base once an operator sends a goal or teleop; until then the demo route.
  driver->set_command_source(
      [&robot_state, &navigator](const RobotSample& sample) -> std::optional<VelocityCommand> {
        const auto snapshot = robot_state.snapshot();
        const auto command = navigator.drive(snapshot ? snapshot->estimate : sample.odometry, sample.stamp);
        if (!command)
          return std::nullopt;
        return VelocityCommand{command->v, command->w};
      });
  std::size_t scans_taken = 0;  // on the driver's thread only
  RobotDriver::Outputs outputs;
  outputs.on_sample = [&robot_state, recorder = recorder.get()](const RobotSample& sample) {
    robot_state.publish(sample);
    if (recorder != nullptr)
      recorder->record(sample);
  };
  outputs.on_scan = [&robot_state, &localizer, &scans_taken, max_scans = options.max_scans,
                     recorder = recorder.get()](ScanEvent scan) {
    robot_state.scan_delivered();  // the sensor works, whether or not the pipeline takes the scan
    if (max_scans != 0 && scans_taken >= max_scans)
      return;  // --max-scans: a run of a fixed length; the map stays as it is
    ++scans_taken;
    if (recorder != nullptr)
      recorder->record(scan);
    localizer.submit(std::move(scan));
  };
  outputs.wait_for_pipeline = [&localizer, &mapping] { return localizer.flush() && mapping.flush(); };
  outputs.on_finished = [&robot_state, kind = driver->kind()] {
    robot_state.set_driver(DriverStatus{kind, true});
  };

  std::string operator_token = options.operator_token;
  if (operator_token.empty())
    operator_token = auth::generate_token();

  boost::asio::io_context io(options.io_threads);
  ServerServices services;
  services.robot = &robot_state;
  services.map = &map_state;
  services.maps = &map_commands;
  services.motion = &navigator;
  services.sim_world = driver->world();  // null for a replay: no simulated world to draw
  services.operator_token = operator_token;
  services.web_root = web_root;
  services.allowed_origins = options.allowed_origins;
  services.max_websocket_clients = options.max_clients;
  services.max_http_connections = options.max_http_connections;
  services.allowed_hosts = auth::own_host_names();
  services.allowed_hosts.insert(services.allowed_hosts.end(), options.allowed_hosts.begin(),
                                options.allowed_hosts.end());
  auto context = std::make_shared<net::ServerContext>(std::move(services));
  const boost::asio::ip::tcp::endpoint endpoint(boost::asio::ip::make_address(options.bind_address),
                                                options.port);
  std::shared_ptr<net::Listener> listener;
  try {
    listener = std::make_shared<net::Listener>(io, endpoint, context, tls);
  } catch (const boost::system::system_error& error) {
    throw std::runtime_error("cannot listen on " + options.bind_address + ":" + std::to_string(options.port) +
                             ": " + error.code().message());
  }
  double last_pose_stamp = -1.0;
  const auto pose_stream_bit = static_cast<std::uint8_t>(protocol::Stream::kPose);
  std::vector<std::shared_ptr<net::PeriodicBroadcast>> broadcasts;
  broadcasts.push_back(std::make_shared<net::PeriodicBroadcast>(
      io, context->hub, options.pose_rate,
      [&robot_state, last_pose_stamp, pose_stream_bit]() mutable -> std::vector<streams::OutgoingMessage> {
        const auto snapshot = robot_state.snapshot();
        if (!snapshot || snapshot->sample.stamp == last_pose_stamp)
          return {};  // nothing new
        last_pose_stamp = snapshot->sample.stamp;
        return {streams::OutgoingMessage::text(protocol::pose_message(*snapshot), "pose", snapshot->sample.stamp,
                                           pose_stream_bit)};
      }));
  broadcasts.push_back(std::make_shared<net::PeriodicBroadcast>(
      io, context->hub, 1.0, [status = &context->status]() -> std::vector<streams::OutgoingMessage> {
        return {streams::OutgoingMessage::text(status->poll(), "status", std::nullopt,
                                           static_cast<std::uint8_t>(protocol::Stream::kStatus))};
      }));
  // The map is pushed, not polled: the mapping thread posts one broadcast of what changed as soon as it
  // publishes a snapshot (issue #7: scan-to-client latency), onto one strand so the frames go out in order.
  // The callback holds references only: the strand and the context outlive the mapping thread, which is
  // stopped below before they go, and destroying the callback must not touch the io_context.
  auto map_strand = boost::asio::make_strand(io);
  if (context->map_stream) {
    mapping.on_published([&map_strand, context = context.get()] {
      boost::asio::post(map_strand, [context] {
        for (const auto& message : context->map_stream->poll())
          context->hub.broadcast(message);
      });
    });
  }
  if (context->navigation_stream) {
    broadcasts.push_back(std::make_shared<net::PeriodicBroadcast>(
        io, context->hub, 20.0, [stream = context->navigation_stream.get()] { return stream->poll(); }));
  }

  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& error, int signal) {
    if (error)
      return;
    spdlog::info("signal {}: shutting down", signal);
    io.stop();
  });

  mapping.start();
  localizer.start();
  navigator.start();
  // However serve() leaves, the driver's thread stops before the pipeline it calls into is destroyed (the
  // driver was made first, for the initial pose, so it is destroyed last).
  struct StopDriver {
    RobotDriver& started;
    ~StopDriver() { started.stop(); }
  } stop_driver{*driver};
  driver->start(std::move(outputs));
  listener->run();
  for (const auto& broadcast : broadcasts)
    broadcast->start();

  const auto bound = listener->local_endpoint();
  spdlog::info("maps directory: {}", maps_dir.string());
  spdlog::info("{}: {}", driver->kind(), driver->description());
  if (!driver->accepts_commands())
    spdlog::info("the {} cannot move: goals are planned on its map, but nothing drives", driver->kind());
  if (recorder)
    spdlog::info("recording to {}", recorder->directory().string());
  if (tls) {
    spdlog::info("TLS on (certificate {}): https:// and wss:// only, plain HTTP is refused",
                 options.tls_certificate.string());
  }
  // A plain line on stdout that scripts and tests wait for; the port is the real one (--port 0 picks).
  if (options.operator_token.empty()) {
    // No token configured: one for this run, shown once to whoever started the server (not logged).
    std::printf("strata: operator token for this run: %s\n", operator_token.c_str());
  }
  // Last: scripts may stop reading stdout once they have the port.
  std::printf("strata: serving on %s://%s:%u\n", tls ? "https" : "http", bound.address().to_string().c_str(),
              static_cast<unsigned>(bound.port()));
  std::fflush(stdout);

  std::vector<std::thread> threads;
  for (int i = 1; i < options.io_threads; ++i)
    threads.emplace_back([&io] { io.run(); });
  io.run();
  for (auto& thread : threads)
    thread.join();

  driver->stop();
  recorder.reset();  // writes what is queued, completes recording.json
  navigator.stop();
  localizer.stop();
  mapping.stop();
  spdlog::info("stopped");
  return 0;
}

}  // namespace strata::app

#include "server/app/serve.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "drivers/sim/simulated_robot.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/net/listener.hpp"
#include "server/net/server_context.hpp"
#include "server/pipeline/localizer_worker.hpp"
#include "server/pipeline/navigator.hpp"
#include "server/pipeline/periodic_broadcast.hpp"
#include "server/protocol/messages.hpp"
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

int serve(const ServeOptions& options) {
  const std::filesystem::path web_root = options.web_root.empty() ? default_web_root() : options.web_root;
  if (!std::filesystem::exists(web_root / "index.html")) {
    spdlog::warn("no web app at {} (build it with the 'web' target); serving the API only",
                 web_root.string());
  }

  RobotState robot_state;
  auto world = std::make_shared<const sim::World>(load_world(options.world));
  sim::SimulatorConfig sim_config;
  sim_config.seed = options.seed;
  sim_config.scanner = parse_scanner(options.scanner);
  sim::Simulator simulator(world, sim_config);
  // The robot is told where it starts (as an operator sets an initial pose): the map frame is the world's.
  const Eigen::Isometry3d start = simulator.sample().truth.to_isometry();
  const Eigen::Isometry3d map_from_odom = start * simulator.sample().odometry.to_isometry().inverse();
  pipeline::LocalizerWorker localizer(robot_state, LocalizerOptions{}, map_from_odom);
  pipeline::Navigator navigator;  // before the robot: the robot's thread asks it for commands
  sim::SimulatedRobot robot(
      std::move(simulator), {.step_rate = 100.0, .time_scale = options.time_scale},
      [&robot_state](const sim::RobotSample& sample) { robot_state.publish(sample); },
      [&localizer](ScanEvent scan) { localizer.submit(std::move(scan)); });
  // The navigator drives the base once an operator sends a goal or teleop; until then the demo route.
  robot.set_command_source(
      [&robot_state, &navigator](const sim::RobotSample& sample) -> std::optional<sim::VelocityCommand> {
        const auto snapshot = robot_state.snapshot();
        const auto command = navigator.drive(snapshot ? snapshot->estimate : sample.odometry, sample.stamp);
        if (!command)
          return std::nullopt;
        return sim::VelocityCommand{command->v, command->w};
      });
  // TODO(map): register navigator.map_listener() with the mapping worker (pipeline::MappingWorker), so
  // goals are planned on the live map; until then every goal fails with "no_map".

  boost::asio::io_context io(options.io_threads);
  // TODO(net): hand &navigator to the ServerContext as its MotionCommands (goal, cancel, teleop; the goal
  // and path streams read navigator.goal_status() and navigator.path()).
  auto context = std::make_shared<net::ServerContext>(robot_state, web_root, &robot.world());
  const boost::asio::ip::tcp::endpoint endpoint(boost::asio::ip::make_address(options.bind_address),
                                                options.port);
  std::shared_ptr<net::Listener> listener;
  try {
    listener = std::make_shared<net::Listener>(io, endpoint, context);
  } catch (const boost::system::system_error& error) {
    throw std::runtime_error("cannot listen on " + options.bind_address + ":" + std::to_string(options.port) +
                             ": " + error.code().message());
  }
  double last_pose_stamp = -1.0;
  auto pose_stream = std::make_shared<pipeline::PeriodicBroadcast>(
      io, context->hub, options.pose_rate,
      [&robot_state, last_pose_stamp]() mutable -> std::optional<net::OutgoingMessage> {
        const auto snapshot = robot_state.snapshot();
        if (!snapshot || snapshot->sample.stamp == last_pose_stamp)
          return std::nullopt;  // nothing new
        last_pose_stamp = snapshot->sample.stamp;
        return net::OutgoingMessage::text(protocol::pose_message(*snapshot), "pose", snapshot->sample.stamp);
      });
  auto status_stream = std::make_shared<pipeline::PeriodicBroadcast>(
      io, context->hub, 1.0, [&robot_state, hub = &context->hub]() -> std::optional<net::OutgoingMessage> {
        return net::OutgoingMessage::text(protocol::status_message(robot_state.registration(), hub->size()),
                                          "status");
      });

  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& error, int signal) {
    if (error)
      return;
    spdlog::info("signal {}: shutting down", signal);
    io.stop();
  });

  localizer.start();
  navigator.start();
  robot.start();
  listener->run();
  pose_stream->start();
  status_stream->start();

  const auto bound = listener->local_endpoint();
  spdlog::info("simulator: world '{}', {} scanner, seed {}, time scale {}", world->description().name,
               options.scanner, options.seed, options.time_scale);
  // A plain line on stdout that scripts and tests wait for; the port is the real one (--port 0 picks).
  std::printf("strata: serving on http://%s:%u\n", bound.address().to_string().c_str(),
              static_cast<unsigned>(bound.port()));
  std::fflush(stdout);

  std::vector<std::thread> threads;
  for (int i = 1; i < options.io_threads; ++i)
    threads.emplace_back([&io] { io.run(); });
  io.run();
  for (auto& thread : threads)
    thread.join();

  robot.stop();
  navigator.stop();
  localizer.stop();
  spdlog::info("stopped");
  return 0;
}

}  // namespace strata::app

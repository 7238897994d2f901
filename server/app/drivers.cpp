#include "server/app/drivers.hpp"

#include <spdlog/fmt/fmt.h>

#include <stdexcept>

#include "drivers/replay/replay_driver.hpp"
#include "drivers/sim/simulator_driver.hpp"

namespace strata::app {
namespace {

replay::OdometrySource parse_odometry_source(const std::string& name) {
  if (name == "auto")
    return replay::OdometrySource::kAuto;
  if (name == "dataset")
    return replay::OdometrySource::kDataset;
  if (name == "reference")
    return replay::OdometrySource::kReference;
  throw std::runtime_error("unknown replay odometry '" + name + "' (auto, dataset, reference)");
}

std::unique_ptr<RobotDriver> make_replay(const ServeOptions& options) {
  replay::ReplayOptions replay;
  if (options.replay.rate != "recorded" && options.replay.rate != "max")
    throw std::runtime_error("unknown replay rate '" + options.replay.rate + "' (recorded, max)");
  replay.as_fast_as_possible = options.replay.rate == "max";
  replay.time_scale = options.time_scale;
  replay.odometry = parse_odometry_source(options.replay.odometry);
  replay.noise.translation = options.replay.noise_translation;
  replay.noise.rotation = options.replay.noise_rotation_deg * 3.14159265358979323846 / 180.0;
  replay.seed = options.seed;
  return std::make_unique<replay::ReplayDriver>(replay::open_dataset(options.replay.directory), replay);
}

std::unique_ptr<RobotDriver> make_simulator(const ServeOptions& options) {
  auto world = std::make_shared<const sim::World>(load_world(options.world));
  sim::SimulatorConfig config;
  config.seed = options.seed;
  config.scanner = parse_scanner(options.scanner);
  const std::string description =
      fmt::format("world '{}', {} scanner, seed {}, time scale {}", world->description().name,
                  options.scanner, options.seed, options.time_scale);
  return std::make_unique<sim::SimulatorDriver>(
      sim::Simulator(std::move(world), config),
      sim::SimulatedRobotConfig{.step_rate = 100.0, .time_scale = options.time_scale}, description);
}

}  // namespace

std::unique_ptr<RobotDriver> make_driver(const ServeOptions& options) {
  if (!options.replay.directory.empty())
    return make_replay(options);
  return make_simulator(options);
}

}  // namespace strata::app

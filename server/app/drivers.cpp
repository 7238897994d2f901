#include "server/app/drivers.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/geometry/pose_text.hpp"
#include "drivers/lidar/lidar_drivers.hpp"
#include "drivers/replay/replay_driver.hpp"
#include "drivers/sim/simulator_driver.hpp"

namespace strata::app {
namespace {

/// Replays and captures share one clock: --time-scale, or --replay-rate max.
PlaybackPacing playback_pacing(const ServeOptions& options) {
  return {.time_scale = options.time_scale, .as_fast_as_possible = options.replay.rate == ReplayRate::kMax};
}

/// --lidar-mount "x,y,z[,roll,pitch,yaw]" (m, degrees): the sensor's pose on the base; not given: nothing
/// (the drivers estimate it from the ground under the sensor).
std::optional<Eigen::Isometry3d> parse_mount(const std::string& text) {
  if (text.empty())
    return std::nullopt;
  try {
    return parse_pose_text(text).to_isometry();
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error("--lidar-mount '" + text + "': " + error.what());
  }
}

std::unique_ptr<RobotDriver> make_replay(const ServeOptions& options) {
  replay::ReplayOptions replay;
  replay.pacing = playback_pacing(options);
  replay.odometry = options.replay.odometry;
  replay.noise.translation = options.replay.noise_translation;
  replay.noise.rotation = options.replay.noise_rotation_deg * std::numbers::pi / 180.0;
  replay.seed = options.seed;
  replay.mount = parse_mount(options.lidar.mount);
  return std::make_unique<replay::ReplayDriver>(replay::open_dataset(options.replay.directory), replay);
}

/// --sim-sensor-outage "START,DURATION": simulated seconds, both finite, START >= 0, DURATION > 0.
sim::SimulatorConfig::SensorOutage parse_outage(const std::string& text) {
  std::vector<double> values;
  try {
    values = parse_number_list(text);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error("--sim-sensor-outage '" + text + "': " + error.what());
  }
  if (values.size() != 2)
    throw std::runtime_error("--sim-sensor-outage '" + text +
                             "': expected START,DURATION (simulated seconds)");
  const sim::SimulatorConfig::SensorOutage outage{values[0], values[1]};
  if (outage.start < 0.0 || outage.duration <= 0.0)
    throw std::runtime_error("--sim-sensor-outage '" + text + "': START must be >= 0 and DURATION > 0");
  return outage;
}

std::unique_ptr<RobotDriver> make_simulator(const ServeOptions& options) {
  auto world = std::make_shared<const sim::World>(load_world(options.world));
  sim::SimulatorConfig config;
  config.seed = options.seed;
  config.scanner = options.scanner;
  // The simulated base climbs what the planner plans for (--max-step, --max-slope): with its own 6 cm and 9
  // degrees it stuck where a ramp's side is 6-8 cm high, on ground the planner judged drivable.
  config.geometry.max_step = options.robot.max_step;
  config.geometry.max_slope_deg = options.robot.max_slope_deg;
  if (!options.sim_imu)
    config.imu.reset();
  std::string description =
      fmt::format("world '{}', {} scanner, {}, seed {}, time scale {}", world->description().name,
                  name_of(kScannerNames, options.scanner), options.sim_imu ? "wheels and IMU" : "wheels only",
                  options.seed, options.time_scale);
  if (!options.sim_sensor_outage.empty()) {
    config.sensor_outage = parse_outage(options.sim_sensor_outage);
    description += fmt::format(", sensor outage drill from t={} s for {} s", config.sensor_outage->start,
                               config.sensor_outage->duration);
  }
  return std::make_unique<sim::SimulatorDriver>(
      sim::Simulator(std::move(world), config),
      sim::SimulatedRobotConfig{.step_rate = 100.0, .time_scale = options.time_scale}, description);
}

std::unique_ptr<RobotDriver> make_lidar(const ServeOptions& options) {
  const LidarParameters& lidar = options.lidar;
  if (lidar.model.empty())
    throw std::runtime_error("--pcap needs --lidar MODEL (vlp16, hdl32e, os1): the capture does not say");
  if (!options.replay.directory.empty())
    throw std::runtime_error("--replay and --lidar/--pcap are two different sources: choose one");
  lidar::LidarDriverOptions driver;
  driver.setup.model = lidar::parse_lidar_model(lidar.model);
  driver.setup.calibration = lidar.calibration;
  driver.setup.port = lidar.port;
  driver.setup.keep_partial = lidar.keep_partial;
  driver.sensor_to_base = parse_mount(lidar.mount);
  if (!lidar.pcap.empty()) {
    try {
      return std::make_unique<lidar::PcapLidarDriver>(lidar.pcap, driver, playback_pacing(options));
    } catch (const std::exception& error) {
      throw std::runtime_error(fmt::format("cannot play {}: {}", lidar.pcap.string(), error.what()));
    }
  }
  try {
    return std::make_unique<lidar::LiveLidarDriver>(driver, lidar.address);
  } catch (const std::exception& error) {
    throw std::runtime_error(fmt::format(
        "cannot listen to the {} lidar on {}:{}: {}", lidar.model, lidar.address,
        lidar.port != 0 ? lidar.port : lidar::default_data_port(driver.setup.model), error.what()));
  }
}

}  // namespace

std::unique_ptr<RobotDriver> make_driver(const ServeOptions& options) {
  const bool simulated =
      options.lidar.pcap.empty() && options.lidar.model.empty() && options.replay.directory.empty();
  if (!simulated && !options.sim_imu)
    throw std::runtime_error("--no-sim-imu is for the simulated robot only");
  if (!simulated && !options.sim_sensor_outage.empty())
    throw std::runtime_error("--sim-sensor-outage is a drill for the simulated robot only");
  if (!options.lidar.pcap.empty() || !options.lidar.model.empty())
    return make_lidar(options);
  if (!options.replay.directory.empty())
    return make_replay(options);
  return make_simulator(options);
}

}  // namespace strata::app

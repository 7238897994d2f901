#include "server/app/serve.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <system_error>

#include "drivers/replay/mcap_recording_writer.hpp"
#include "drivers/replay/recorder.hpp"
#include "drivers/robot_driver.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/app/drivers.hpp"
#include "server/auth/host_policy.hpp"
#include "server/auth/operator_token.hpp"
#include "server/net/network_server.hpp"
#include "server/pipeline/robot_pipeline.hpp"
#include "server/protocol/build_info.hpp"

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

std::filesystem::path default_imu_calibration_file() {
  const char* state_home = std::getenv("XDG_STATE_HOME");
  if (state_home != nullptr && *state_home == '/')
    return std::filesystem::path(state_home) / "strata" / "imu-calibration.json";
  const char* home = std::getenv("HOME");
  if (home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".local" / "state" / "strata" / "imu-calibration.json";
  return "imu-calibration.json";
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

namespace {

// --record and --record-mcap: every sample and scan the pipeline receives, each on its recorder's thread.
std::vector<std::unique_ptr<replay::Recorder>> make_recorders(const ServeOptions& options,
                                                              const RobotDriver& driver) {
  std::vector<std::unique_ptr<replay::Recorder>> recorders;
  if (options.record.empty() && options.record_mcap.empty())
    return recorders;
  const bool simulated = driver.world() != nullptr;
  const nlohmann::json metadata{{"source", driver.kind()},
                                {"description", driver.description()},
                                {"seed", options.seed},
                                {"time_scale", options.time_scale},
                                {"world", simulated ? options.world : ""},
                                {"scanner", simulated ? name_of(kScannerNames, options.scanner) : ""},
                                {"strata_version", build_info::version()}};
  if (!options.record.empty())
    recorders.push_back(
        std::make_unique<replay::Recorder>(options.record, metadata, driver.initial_map_from_odom()));
  if (!options.record_mcap.empty()) {
    recorders.push_back(std::make_unique<replay::Recorder>(
        std::make_unique<replay::McapRecordingWriter>(
            options.record_mcap, metadata, driver.initial_map_from_odom(),
            options.record_mcap_uncompressed ? mcap::Compression::kNone : mcap::Compression::kZstd),
        replay::Recorder::Limits{}));
  }
  return recorders;
}

pipeline::PipelineOptions pipeline_options(const ServeOptions& options) {
  pipeline::PipelineOptions pipeline;
  pipeline.robot = options.robot;
  pipeline.maps_dir = options.maps_dir.empty() ? default_maps_dir() : options.maps_dir;
  // A stalled sensor: 10 s of wall time waiting for a due scan, stretched when --time-scale is below 1 (the
  // simulated scanner then takes longer per scan).
  pipeline.sensor_timeout =
      options.sensor_timeout > 0.0 ? options.sensor_timeout : 10.0 * std::max(1.0, 1.0 / options.time_scale);
  pipeline.max_scans = options.max_scans;
  pipeline.initial_map = options.map;
  pipeline.initial_map_mode = options.map_mode;
  if (options.keep_imu_calibration)
    pipeline.imu_calibration_file =
        options.imu_calibration.empty() ? default_imu_calibration_file() : options.imu_calibration;
  return pipeline;
}

/// The network options as the server runs with them: the web root found, a token made when none is given,
/// the machine's own names among the allowed hosts, the robot's size in the fleet's factsheet.
NetworkOptions network_as_run(const ServeOptions& options) {
  NetworkOptions network = options.network;
  network.fleet.robot_radius = options.robot.radius;
  network.fleet.robot_height = options.robot.height;
  network.fleet.max_speed = pipeline::NavigatorConfig{}.max_speed;
  if (network.web_root.empty())
    network.web_root = default_web_root();
  if (!std::filesystem::exists(network.web_root / "index.html")) {
    spdlog::warn("no web app at {} (build it with the 'web' target); serving the API only",
                 network.web_root.string());
  }
  if (network.operator_token.empty())
    network.operator_token = auth::generate_token();
  auto hosts = auth::own_host_names();
  hosts.insert(hosts.end(), network.allowed_hosts.begin(), network.allowed_hosts.end());
  network.allowed_hosts = std::move(hosts);
  return network;
}

/// The log lines of a start, and the plain lines on stdout that scripts and tests wait for.
void announce(const ServeOptions& options, const RobotDriver& driver, const net::NetworkServer& network,
              const std::string& operator_token) {
  spdlog::info("maps directory: {}", pipeline_options(options).maps_dir.string());
  spdlog::info("{}: {}", driver.kind(), driver.description());
  if (!driver.accepts_commands())
    spdlog::info("the {} cannot move: goals are planned on its map, but nothing drives", driver.kind());
  if (!options.record.empty())
    spdlog::info("recording to {}", options.record.string());
  if (!options.record_mcap.empty())
    spdlog::info("recording to {} (MCAP; {} until it is finished)", options.record_mcap.string(),
                 replay::McapRecordingWriter::partial_path(options.record_mcap).string());
  if (network.tls()) {
    spdlog::info("TLS on (certificate {}): https:// and wss:// only, plain HTTP is refused",
                 options.network.tls_certificate.string());
  }
  // No token configured: one for this run, shown once to whoever started the server (not logged).
  if (options.network.operator_token.empty())
    std::printf("strata: operator token for this run: %s\n", operator_token.c_str());
  // Last: scripts may stop reading stdout once they have the port (the real one: --port 0 picks).
  const auto bound = network.local_endpoint();
  std::printf("strata: serving on %s://%s:%u\n", network.tls() ? "https" : "http",
              bound.address().to_string().c_str(), static_cast<unsigned>(bound.port()));
  std::fflush(stdout);
}

/// The token in a file, without surrounding whitespace; throws when the file cannot be read.
std::string read_token_file(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string token;
  if (!file || !std::getline(file, token))
    throw std::runtime_error("cannot read the operator token from " + path.string());
  const auto first = token.find_first_not_of(" \t\r");
  const auto last = token.find_last_not_of(" \t\r");
  return first == std::string::npos ? std::string() : token.substr(first, last - first + 1);
}

/// Stops the pipeline however serve() leaves, before the network it publishes to goes.
struct StopOnExit {
  pipeline::RobotPipeline& robot;
  ~StopOnExit() { robot.stop(); }
};

}  // namespace

int serve(const ServeOptions& options) {
  // A write past the file size limit (RLIMIT_FSIZE) then fails with EFBIG, so a map save reports io_error
  // and leaves the previous file, instead of the signal's default action killing the robot's server.
  std::signal(SIGXFSZ, SIG_IGN);
  // The driver first: a world, a dataset or a capture that cannot be used stops the start with its name.
  std::unique_ptr<RobotDriver> driver = make_driver(options);
  auto recorders = make_recorders(options, *driver);
  pipeline::RobotPipeline robot(std::move(driver), std::move(recorders), pipeline_options(options));
  ServerServices services = robot.services();
  services.network = network_as_run(options);
  net::NetworkServer network(services);  // a bad certificate, address or port stops the start here
  robot.on_map_published(network.map_publisher());
  robot.start();
  const StopOnExit stop_robot{robot};
  network.start();
  announce(options, robot.driver(), network, services.network.operator_token);
  network.run();  // until SIGINT or SIGTERM
  robot.stop();
  spdlog::info("stopped");
  return 0;
}

int run_serve(ServeOptions options) {
  if (!options.network.operator_token_file.empty())
    options.network.operator_token = read_token_file(options.network.operator_token_file);
  if (!options.network.operator_token.empty() && !auth::is_valid_token(options.network.operator_token)) {
    throw std::runtime_error(
        "the operator token must be 16-128 characters of A-Z a-z 0-9 - _ (it travels in headers and "
        "WebSocket subprotocols)");
  }
  return serve(options);
}

}  // namespace strata::app

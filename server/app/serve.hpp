#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "drivers/replay/replay_driver.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"
#include "server/control/network_options.hpp"
#include "server/pipeline/robot_pipeline.hpp"

namespace strata::app {

/// How a dataset or a capture is paced.
enum class ReplayRate {
  kRecorded,  ///< at the dataset's clock times --time-scale
  kMax,       ///< as fast as the pipeline takes the scans, none dropped
};

/// The names the command line and the config file use for the option values.
inline const std::map<std::string, sim::ScannerKind> kScannerNames{{"tilting", sim::ScannerKind::kTilting},
                                                                   {"lidar", sim::ScannerKind::kLidar},
                                                                   {"none", sim::ScannerKind::kNone}};
inline const std::map<std::string, ReplayRate> kReplayRateNames{{"recorded", ReplayRate::kRecorded},
                                                                {"max", ReplayRate::kMax}};
inline const std::map<std::string, replay::OdometrySource> kOdometrySourceNames{
    {"auto", replay::OdometrySource::kAuto},
    {"dataset", replay::OdometrySource::kDataset},
    {"reference", replay::OdometrySource::kReference},
    {"none", replay::OdometrySource::kNone}};

/// The name of an option value, for logs and recordings.
template <class Enum>
[[nodiscard]] std::string name_of(const std::map<std::string, Enum>& names, Enum value) {
  for (const auto& [name, known] : names)
    if (known == value)
      return name;
  return "?";
}

/// Playing a dataset instead of simulating (strata serve --replay DIR).
struct ReplayParameters {
  std::filesystem::path directory;  ///< empty: the simulator
  ReplayRate rate = ReplayRate::kRecorded;
  replay::OdometrySource odometry = replay::OdometrySource::kAuto;
  double noise_translation = 0.0;   ///< m per m driven, 1-sigma, for odometry made from reference poses
  double noise_rotation_deg = 0.0;  ///< degrees of heading per m driven, 1-sigma
};

/// A lidar instead of the simulator: a packet capture played (--pcap FILE --lidar MODEL) or the live sensor
/// (--lidar MODEL alone). Pacing of a capture: ReplayParameters::rate and ServeOptions::time_scale.
struct LidarParameters {
  std::string model;                  ///< vlp16, hdl32e, os1 (lidar::parse_lidar_model); empty: no lidar
  std::filesystem::path pcap;         ///< empty: live UDP
  std::filesystem::path calibration;  ///< Velodyne YAML (optional), Ouster metadata JSON (required)
  std::uint16_t port = 0;             ///< live UDP port; 0: the model's (2368 Velodyne, 7502 Ouster)
  std::string address = "0.0.0.0";    ///< live: the address to receive on
  /// x,y,z[,roll,pitch,yaw] of the sensor on the base, m and degrees; empty: estimated from the ground
  std::string mount;
  bool keep_partial = false;  ///< also hand on partial revolutions (stream ends, dropped packets)
};

/// Everything `strata serve` is told (server/app/serve_command.cpp declares the options).
struct ServeOptions {
  NetworkOptions network;
  pipeline::RobotParameters robot;
  // Where the scans come from: the simulator by default, else a replay or a lidar.
  std::uint64_t seed = 1;  ///< same seed, same simulated run (and the same replay noise)
  double time_scale = 1.0;
  std::string world = "campus";  ///< a built-in world's name or a world file's path
  sim::ScannerKind scanner = sim::ScannerKind::kTilting;
  ReplayParameters replay;
  LidarParameters lidar;
  /// A fault drill with the simulator: "START,DURATION", simulated seconds from the start during which
  /// the sensor delivers nothing; empty: none.
  std::string sim_sensor_outage;
  /// The simulated base's IMU: its gyro turns the odometry and its gravity reading goes with each scan.
  /// Off: wheels alone, as on a base without one.
  bool sim_imu = true;
  std::filesystem::path maps_dir;  ///< saved maps; empty: default_maps_dir()
  std::string map;                 ///< a saved map in maps_dir to start with; empty: none
  MapMode map_mode = MapMode::kMapping;
  /// Where the IMU calibration is kept between runs; empty: default_imu_calibration_file().
  std::filesystem::path imu_calibration;
  bool keep_imu_calibration = true;   ///< false: none is loaded or kept (--no-imu-calibration)
  std::filesystem::path record;       ///< write the scans and odometry here (replay layout); empty: none
  std::filesystem::path record_mcap;  ///< record the run into this MCAP file of ROS 2 messages; empty: none
  bool record_mcap_uncompressed = false;  ///< --record-mcap without zstd
  std::size_t max_scans = 0;              ///< hand at most this many scans to the pipeline; 0: all
  /// Wall-clock seconds a due scan may be late before the status says the sensor stalled; 0: 10 s, longer
  /// when --time-scale slows the simulator down.
  double sensor_timeout = 0.0;
};

/// Runs the server with the simulated robot, a replay or a lidar until SIGINT or SIGTERM. Returns the
/// process exit code.
int serve(const ServeOptions& options);

/// Reads the operator token file if one is given, checks the token, and runs the server (serve()).
int run_serve(ServeOptions options);

/// A built-in world by name, or a world file by path; throws with the choices when neither exists.
[[nodiscard]] sim::WorldDescription load_world(const std::string& name_or_path);

/// Where saved maps live when no --maps-dir is given: $XDG_DATA_HOME/strata/maps, else
/// ~/.local/share/strata/maps (the XDG default), else ./maps when there is no HOME either.
[[nodiscard]] std::filesystem::path default_maps_dir();

/// Where the IMU calibration is kept when no --imu-calibration is given:
/// $XDG_STATE_HOME/strata/imu-calibration.json, else ~/.local/state/strata/imu-calibration.json (the XDG
/// default: state that outlives a run but is no document), else ./imu-calibration.json.
[[nodiscard]] std::filesystem::path default_imu_calibration_file();

/// Where the web bundle is when none is given: `web/` next to the executable (a build tree), or
/// `../share/strata/web` from it (an installed package).
[[nodiscard]] std::filesystem::path default_web_root();

}  // namespace strata::app

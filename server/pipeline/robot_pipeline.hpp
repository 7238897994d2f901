#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "drivers/replay/recorder.hpp"
#include "drivers/robot_driver.hpp"
#include "server/control/server_services.hpp"
#include "server/pipeline/imu_calibration_store.hpp"
#include "server/pipeline/localizer_worker.hpp"
#include "server/pipeline/mapping_worker.hpp"
#include "server/pipeline/navigator.hpp"
#include "server/pipeline/run_recording.hpp"
#include "server/state/map_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata::pipeline {

/// The robot's body and what it can climb: what the drivable map and the planner assume.
/// Defaults: the thesis's wheelchair.
struct RobotParameters {
  double radius = 0.45;         ///< m; the planner keeps the robot's centre this far from edges
  double height = 1.0;          ///< m; free space needed above a surface to drive there
  double max_step = 0.08;       ///< m; highest step between neighbouring cells
  double max_slope_deg = 15.0;  ///< steepest drivable ground
};

struct PipelineOptions {
  RobotParameters robot;
  std::filesystem::path maps_dir;  ///< saved maps
  /// Wall-clock seconds a due scan may be late before the status says the sensor stalled.
  double sensor_timeout = 10.0;
  std::size_t max_scans = 0;  ///< hand at most this many scans on, then keep the map as it is; 0: all
  /// A saved map (a name in maps_dir) to load at start, and what for; empty: start with no map.
  std::string initial_map;
  MapMode initial_map_mode = MapMode::kMapping;
  /// Where the IMU calibration is kept between runs (ImuCalibrationStore); empty: nowhere.
  std::filesystem::path imu_calibration_file;
  /// Threads a scan's registration may use; empty: the localizer's default (two). One measures a scan's
  /// whole cost on the localizer's own thread (strata_sequence_bench --threads 1).
  std::optional<unsigned> registration_threads;
};

/// One running robot: the driver and everything a scan passes through on its way into the map, and the
/// navigator that drives the base (docs/architecture.md 3). Owns them as members in the order they must
/// live (the state the others write is made first and goes last) and wires them in named steps, one per
/// arrow of the data flow. The network side reads and commands it through services().
class RobotPipeline {
 public:
  /// `recorders` may be empty (no --record, no --record-mcap).
  RobotPipeline(std::unique_ptr<RobotDriver> driver, std::vector<std::unique_ptr<replay::Recorder>> recorders,
                const PipelineOptions& options);
  /// Stops everything first (stop()).
  ~RobotPipeline();
  RobotPipeline(const RobotPipeline&) = delete;
  RobotPipeline& operator=(const RobotPipeline&) = delete;

  /// Before start(): called on the mapping thread each time a new map snapshot is published (the network
  /// pushes what changed). Whatever it reaches must outlive stop().
  void on_map_published(std::function<void()> callback);
  /// Before start(): called on the localizer's thread after every scan it processed (benchmarks).
  void on_scan_localized(LocalizerWorker::ScanObserver observer) { scan_observer_ = std::move(observer); }

  /// Starts the workers, loads the initial map if there is one (throws std::runtime_error saying why when
  /// it cannot), then starts the driver's thread.
  void start();
  /// Stops the driver first (nothing new comes in), then the navigator, the localizer and the mapping
  /// worker, then the recordings (flushed and finished). Idempotent.
  void stop();

  /// The state and commands the network side serves; NetworkOptions left at their defaults.
  [[nodiscard]] ServerServices services();
  [[nodiscard]] const RobotDriver& driver() const { return *driver_; }

 private:
  // The steps of docs/architecture.md 3, each wiring one arrow.
  void take_scans_from_the_driver();         // driver thread -> state, recorder, localizer
  void map_the_registered_scans();           // localizer (steps 1-5) -> mapping (6-8)
  void plan_on_the_live_map();               // mapping (step 8) -> navigator
  void drive_the_base_from_the_navigator();  // navigator -> driver (goals, teleop)
  void record_what_the_server_works_out();   // localizer, navigator, mapping -> recordings

  RobotState robot_state_;
  std::unique_ptr<RobotDriver> driver_;
  RunRecording recording_;
  Navigator navigator_;
  MapState map_state_;
  MappingWorker mapping_;
  ImuCalibrationStore calibration_;  // before the localizer, which saves into it
  LocalizerWorker localizer_;
  RobotDriver::Outputs outputs_;                 // handed to the driver at start()
  LocalizerWorker::ScanObserver scan_observer_;  // on_scan_localized
  std::size_t max_scans_ = 0;
  std::string initial_map_;
  MapMode initial_map_mode_ = MapMode::kMapping;
  std::size_t scans_taken_ = 0;  // on the driver's thread only
  bool started_ = false;
  bool stopped_ = false;
};

}  // namespace strata::pipeline

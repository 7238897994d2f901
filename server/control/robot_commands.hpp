#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/localization/pose_estimate.hpp"
#include "server/control/error_code.hpp"
#include "server/state/goal_state.hpp"
#include "server/state/robot_state.hpp"

namespace strata {

/// The answer to an operator command: ok, or a protocol error code (proto/PROTOCOL.md) and a message.
struct CommandResult {
  bool ok = true;
  ErrorCode code = ErrorCode::kInternal;  ///< when not ok
  std::string message;
  std::uint64_t goal_id = 0;  ///< set_goal: the id of the goal it accepted
  static CommandResult success() { return {}; }
  static CommandResult failure(ErrorCode code, std::string message) {
    return {false, code, std::move(message)};
  }
};

/// What operators may ask of the robot's motion. The network side (WebSocket and REST) calls these from
/// its threads; the implementation (pipeline::Navigator) makes them thread-safe and quick.
class MotionCommands {
 public:
  virtual ~MotionCommands() = default;
  /// Replaces any active goal. The answer only says whether the request was well-formed and accepted;
  /// planning and driving are reported through goal_status().
  virtual CommandResult set_goal(const GoalRequest& goal) = 0;
  /// Cancels the active goal and stops the robot.
  virtual CommandResult cancel_goal() = 0;
  /// Cancels goal `goal_id` with `reason` and stops the robot, but only while that goal is still the active
  /// one: the WebSocket operator connection that set it closed. A goal replaced since, reached, failed or
  /// cancelled is left alone. Returns whether it cancelled.
  virtual bool cancel_goal_if_active(std::uint64_t goal_id, const std::string& reason) = 0;
  /// Drives at (v m/s, w rad/s) until 0.5 s after `sent` (when the operator sent it, steady clock) unless
  /// renewed; overrides (and cancels) a goal. Whether a command is fresh enough to obey is decided before
  /// (TeleopFreshness): the lease only never outlives the intent it carries.
  virtual CommandResult teleop(double v, double w, std::chrono::steady_clock::time_point sent) = 0;
  /// Stops teleoperation at once (the teleoperating client disconnected).
  virtual void stop_teleop() = 0;
  [[nodiscard]] virtual GoalStatus goal_status() const = 0;
  /// Null when there is no path.
  [[nodiscard]] virtual std::shared_ptr<const PlannedPath> path() const = 0;
};

struct MapFileInfo {
  std::string name;  ///< file name inside the maps directory
  std::uintmax_t bytes = 0;
  double modified = 0.0;  ///< seconds since the epoch
};

/// A map download and the map version it shows.
struct MapDownload {
  std::vector<std::uint8_t> bytes;  ///< empty: nothing to download yet, or the version asked for is gone
  std::uint64_t version = 0;        ///< of the map the bytes show
  bool version_gone = false;        ///< a version was asked for that the server no longer has
  bool reused = false;              ///< the bytes of an earlier request for the same map and format
};

/// One immutable version of a saved map on the map server (docs/fleet.md, "The map server"): every save
/// makes one (numbered 1, 2, ... per name), a fleet's downloadMap stores one under the name and version the
/// master gives. Never written again once there; removed only by deleteMap.
struct MapVersionInfo {
  std::string name;     ///< the map's name (a map store name)
  std::string version;  ///< A-Z a-z 0-9 . _ -, as map names
  std::uintmax_t bytes = 0;
  std::string sha256;           ///< of the file, 64 lowercase hex digits
  std::vector<double> heights;  ///< m: the ground heights its robot drove at (keyframes, 0.25 m apart)
};

/// A map version's file, for the map server's REST endpoint.
struct MapVersionFile {
  CommandResult result;  ///< kNotFound, kIoError
  MapVersionInfo info;
  std::string bytes;
};

/// Saving and loading the map (pipeline::MappingWorker). Names are plain file names inside the configured
/// maps directory, never paths.

/// Telling the localizer where the robot is (pipeline::LocalizerWorker).
class LocalizationCommands {
 public:
  virtual ~LocalizationCommands() = default;
  /// At the next scan the robot is searched for around `estimate` in the map it localizes in and, when
  /// found, placed there; the status's `relocalization` says how it went. kBadParams when it localizes in
  /// no saved map (mapping: the map is where the robot's scans put it) or the estimate is not finite.
  virtual CommandResult set_pose_estimate(const PoseEstimate& estimate) = 0;
};

/// The IMU calibration the server keeps between runs of the robot (pipeline::ImuCalibrationStore). Any
/// thread.
class CalibrationCommands {
 public:
  virtual ~CalibrationCommands() = default;
  [[nodiscard]] virtual ImuCalibrationStatus imu_calibration() const = 0;
  /// Forgets the kept calibration (the IMU was mounted again): the next run starts from none. This run
  /// goes on from what it started with, and keeps its own estimate again at its next loop closure.
  /// kUnavailable when nothing is kept (off), kIoError when the file cannot be removed.
  virtual CommandResult clear_imu_calibration() = 0;
};

/// What a loaded map is for (docs/architecture.md 4.1, "Localizing in a saved map").
enum class MapMode {
  kMapping,   ///< it replaces the live map, and the scans go on into it
  kLocalize,  ///< it is fixed: the scans are registered against it and change nothing
};
[[nodiscard]] inline std::string_view to_string(MapMode mode) {
  return mode == MapMode::kLocalize ? "localize" : "mapping";
}
/// "mapping" or "localize"; none for anything else.
[[nodiscard]] inline std::optional<MapMode> map_mode_from_string(std::string_view text) {
  if (text == "mapping")
    return MapMode::kMapping;
  if (text == "localize")
    return MapMode::kLocalize;
  return std::nullopt;
}

class MapCommands {
 public:
  virtual ~MapCommands() = default;
  /// Saves the live map with what localizing in it needs (the pose graph's keyframes).
  virtual CommandResult save_map(const std::string& name) = 0;
  /// Loads a saved map for `mode`. A map saved without localization data (an older file) loads for mapping
  /// only, and the success's message says so; for localizing it is refused with kBadParams.
  virtual CommandResult load_map(const std::string& name, MapMode mode) = 0;
  [[nodiscard]] virtual std::vector<MapFileInfo> list_maps() const = 0;
  /// The current map for download: "strata" (the native file), "ply" (patches as points and boxes),
  /// "pgm" and "yaml" (the drivable map at the robot's level over the whole map, ROS map_server). For
  /// those two, `version` asks for the one of that map version (the version a YAML named), which the
  /// server keeps until the next download of a newer one: a PGM and a YAML fetched apart then agree.
  [[nodiscard]] virtual MapDownload download(const std::string& format,
                                             std::optional<std::uint64_t> version) const = 0;

  // The map server's immutable versions (MapVersionInfo). A server without them answers kUnavailable.
  [[nodiscard]] virtual std::vector<MapVersionInfo> list_map_versions() const { return {}; }
  [[nodiscard]] virtual MapVersionFile read_map_version(const std::string& /*name*/,
                                                        const std::string& /*version*/) const {
    return {unavailable(), {}, {}};
  }
  /// Stores `bytes` as version `version` of map `name`, DISABLED (the map in use is not touched): checked
  /// against `sha256` when that is not empty (kBadParams), checked whole as a load checks a file
  /// (kCorruptFile), refused when that version is there already (kBadParams). Nothing is stored on a failure.
  virtual CommandResult add_map_version(const std::string& /*name*/, const std::string& /*version*/,
                                        std::string_view /*bytes*/, std::string_view /*sha256*/) {
    return unavailable();
  }
  /// Loads a stored version as load_map() loads a map by name; the snapshot then names the version.
  virtual CommandResult load_map_version(const std::string& /*name*/, const std::string& /*version*/,
                                         MapMode /*mode*/) {
    return unavailable();
  }
  /// Removes a stored version; refused (kBadParams) while the robot uses it.
  virtual CommandResult delete_map_version(const std::string& /*name*/, const std::string& /*version*/) {
    return unavailable();
  }

 private:
  static CommandResult unavailable() {
    return CommandResult::failure(ErrorCode::kUnavailable, "this server keeps no map versions");
  }
};

}  // namespace strata

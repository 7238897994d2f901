#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace strata::fleet {

/// The protocol version Strata speaks (the header's "version"); the topics carry its major, "v2".
inline constexpr std::string_view kVdaVersion = "2.1.0";

/// Who this vehicle is on the broker: topics `<interface>/v2/<manufacturer>/<serialNumber>/<topic>`.
struct VehicleId {
  std::string interface_name;
  std::string manufacturer;
  std::string serial_number;
  [[nodiscard]] std::string topic(std::string_view name) const;
};

/// Every message's header; header ids count per topic from 0 (VDA 5050 2.1, 6.1).
class HeaderStamp {
 public:
  explicit HeaderStamp(const VehicleId& id) : id_(id) {}
  /// `body` with headerId, timestamp (UTC, ISO 8601 with milliseconds), version, manufacturer, serialNumber.
  [[nodiscard]] nlohmann::json stamp(nlohmann::json body, std::chrono::system_clock::time_point now);

 private:
  const VehicleId& id_;
  std::uint32_t next_ = 0;
};

/// "2026-12-02T15:20:45.123Z".
[[nodiscard]] std::string iso_timestamp(std::chrono::system_clock::time_point time);

struct AgvPosition {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;  ///< rad, in (-pi, pi]
  std::string map_id;
  bool initialized = false;
  std::optional<double> localization_score;  ///< [0, 1]
  std::optional<double> deviation_range;     ///< m
};

struct Velocity {
  double vx = 0.0;  ///< m/s along the vehicle's heading
  double omega = 0.0;
};

struct MapEntry {
  std::string map_id;
  std::string map_version;
  bool enabled = true;
};

struct VehicleError {
  std::string type;
  std::string level;  ///< WARNING or FATAL
  std::string description;
  std::vector<std::pair<std::string, std::string>> references;  ///< referenceKey, referenceValue
};

struct ActionState {
  std::string action_id;
  std::string action_type;
  std::string status;  ///< WAITING, INITIALIZING, RUNNING, PAUSED, FINISHED, FAILED
  std::string result;  ///< resultDescription; empty: none
};

/// A node still to pass (state.nodeStates), with the position the order gave it.
struct NodeState {
  std::string node_id;
  std::uint32_t sequence_id = 0;
  bool released = false;
  double x = 0.0;
  double y = 0.0;
  std::optional<double> theta;
  std::string map_id;
};

/// An edge still to pass (state.edgeStates).
struct EdgeState {
  std::string edge_id;
  std::uint32_t sequence_id = 0;
  bool released = false;
};

/// What `state` says, before its header.
struct VehicleReport {
  std::optional<AgvPosition> position;  ///< none before the robot's first sample
  std::optional<Velocity> velocity;
  std::vector<MapEntry> maps;
  std::vector<VehicleError> errors;
  std::vector<ActionState> actions;
  bool driving = false;
  bool paused = false;
  std::string order_id;  ///< empty: never an order
  std::uint64_t order_update_id = 0;
  std::string last_node_id;
  std::uint32_t last_node_sequence_id = 0;
  std::vector<NodeState> node_states;
  std::vector<EdgeState> edge_states;
};

[[nodiscard]] nlohmann::json state_body(const VehicleReport& report);
[[nodiscard]] nlohmann::json visualization_body(const VehicleReport& report);
/// ONLINE, OFFLINE or CONNECTIONBROKEN.
[[nodiscard]] nlohmann::json connection_body(std::string_view connection_state);

/// The factsheet's physical facts: from the robot's options.
struct VehicleFacts {
  double radius = 0.45;    ///< m
  double height = 1.0;     ///< m
  double max_speed = 0.6;  ///< m/s
};
[[nodiscard]] nlohmann::json factsheet_body(const VehicleFacts& facts);

/// The instant actions this vehicle carries out (the factsheet lists them).
[[nodiscard]] const std::vector<std::string>& supported_instant_actions();

}  // namespace strata::fleet

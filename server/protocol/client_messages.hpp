#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "server/control/robot_commands.hpp"
#include "server/control/teleop_freshness.hpp"
#include "server/protocol/messages.hpp"
#include "server/state/goal_state.hpp"

namespace strata::protocol {

/// The streams a client can subscribe to (proto/PROTOCOL.md, "Streams"); a bit each.
enum class Stream : std::uint8_t {
  kPose = 1U << 0U,
  kStatus = 1U << 1U,
  kTiles = 1U << 2U,
  kOccupancy = 1U << 3U,
  kPath = 1U << 4U,
  kGoal = 1U << 5U,
};
using StreamSet = std::uint8_t;
inline constexpr StreamSet kAllStreams = 0x3F;
[[nodiscard]] constexpr bool contains(StreamSet set, Stream stream) {
  return (set & static_cast<StreamSet>(stream)) != 0;
}
[[nodiscard]] std::optional<Stream> stream_from_name(std::string_view name);

struct PingRequest {};
struct SubscribeRequest {
  StreamSet streams = kAllStreams;
};
struct SetGoalRequest {
  GoalRequest goal;
};
struct CancelGoalRequest {};
struct TeleopRequest {
  double v = 0.0;                    ///< m/s, forward positive
  double w = 0.0;                    ///< rad/s, counter-clockwise positive
  std::optional<TeleopStamp> stamp;  ///< "seq" and "t": what tells a stale command (TeleopFreshness)
  [[nodiscard]] bool moves() const { return v != 0.0 || w != 0.0; }
};
struct SaveMapRequest {
  std::string name;
};
struct SetPoseRequest {
  PoseEstimate estimate;
};
struct LoadMapRequest {
  std::string name;
  MapMode mode = MapMode::kMapping;
};

using ClientRequest = std::variant<PingRequest, SubscribeRequest, SetGoalRequest, CancelGoalRequest,
                                   TeleopRequest, SaveMapRequest, LoadMapRequest, SetPoseRequest>;

/// A client message, validated: either a request or the error to answer it with. `id` is the message's
/// optional "id" (any JSON scalar), echoed in the reply so a client can match answers to requests.
struct ParsedClientMessage {
  std::optional<ClientRequest> request;
  std::string op;
  nlohmann::json id;
  ErrorCode error = ErrorCode::kBadMessage;
  std::string error_message;
};

/// Parses and validates one text frame against proto/schemas/ws-client: JSON nested at most
/// io::kMaxJsonDepth levels, an object with a known string "op", exactly the fields that op allows, of the
/// right types and in range (finite numbers, sane bounds).
[[nodiscard]] ParsedClientMessage parse_client_message(std::string_view text);
/// The same for a message already parsed (a REST body with its endpoint's "op" added).
[[nodiscard]] ParsedClientMessage validate_client_message(const nlohmann::json& message);

/// Goals, teleop, save and load move the robot or change the map: operators only.
[[nodiscard]] bool needs_operator(const ClientRequest& request);

/// Limits on client values (also in the schemas).
inline constexpr double kMaxCoordinate = 1.0e6;  ///< metres from the map origin
inline constexpr double kMaxTeleopSpeed = 2.0;   ///< m/s; the base clamps further to its own limits
inline constexpr double kMaxTeleopTurn = 3.0;    ///< rad/s
inline constexpr double kMaxClockMs = 1.0e15;    ///< teleop "t": the server clock, ms (31,000 years)

/// A map file name: 1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot. Never a path.
[[nodiscard]] bool is_valid_map_name(std::string_view name);

}  // namespace strata::protocol

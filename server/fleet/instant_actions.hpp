#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/fleet/vda_messages.hpp"

namespace strata::fleet {

/// The largest instantActions message taken; larger ones are refused unread (an instant action is a few
/// hundred bytes; a master sends a handful at once).
inline constexpr std::size_t kMaxInstantActionsBytes = 64 * 1024;
/// The most actions one message may carry.
inline constexpr std::size_t kMaxInstantActions = 32;

/// initPosition's parameters (VDA 5050 2.1, 6.8.2).
struct InitPosition {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
  std::string map_id;
  std::string last_node_id;
};

/// downloadMap's, enableMap's and deleteMap's parameters (VDA 5050 2.1, 6.7 and 6.8.1).
struct MapAction {
  std::string map_name;       ///< the mapId's map: "yard.smls" of "yard.smls@0" (all its levels are one file)
  std::string map_version;    ///< a version's name (A-Z a-z 0-9 . _ -)
  std::string download_link;  ///< downloadMap: http:// or https://
  std::string hash;           ///< downloadMap: SHA-256 in hex, or empty
};

struct InstantAction {
  std::string action_id;
  std::string action_type;                    ///< one of supported_instant_actions()
  std::optional<InitPosition> init_position;  ///< for initPosition
  std::optional<MapAction> map;               ///< for downloadMap, enableMap, deleteMap
};

/// A message on the instantActions topic, checked whole: either every action in it is well-formed and one
/// this vehicle carries out, or none is taken and `error` says why (with the actionId where one is known).
struct InstantActionsMessage {
  std::vector<InstantAction> actions;
  std::optional<std::uint64_t> header_id;
  std::string error;         ///< empty: taken
  std::string error_action;  ///< the actionId the error is about, where there is one
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Parses and validates an instantActions payload addressed to `vehicle` (VDA 5050 2.1's instantActions
/// schema, plus: the actions known, their parameters' types, unique actionIds, the sizes above).
[[nodiscard]] InstantActionsMessage parse_instant_actions(std::string_view payload, const VehicleId& vehicle);

}  // namespace strata::fleet

// VDA 5050 instantActions from the broker (any client that may publish on the vehicle's topic): parse and
// validate whole (server/fleet/instant_actions.*).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "server/fleet/instant_actions.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const strata::fleet::VehicleId vehicle{"uagv", "Strata", "robot-1"};
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const strata::fleet::InstantActionsMessage message = strata::fleet::parse_instant_actions(text, vehicle);
  if (!message.ok()) {
    if (!message.actions.empty())
      __builtin_trap();  // nothing of a refused message is carried out
    return 0;
  }
  if (message.actions.size() > strata::fleet::kMaxInstantActions)
    __builtin_trap();
  for (const auto& action : message.actions) {
    if (action.action_id.empty())
      __builtin_trap();
    if (action.action_type == "initPosition") {
      if (!action.init_position || !std::isfinite(action.init_position->x) ||
          !std::isfinite(action.init_position->y) || !std::isfinite(action.init_position->theta))
        __builtin_trap();  // the pose estimate handed on is always a number
    }
  }
  return 0;
}

// VDA 5050 orders from the broker (any client that may publish on the vehicle's topic): parse and validate
// whole (server/fleet/order.*), then the update rules (server/fleet/order_progress.*) on what was taken.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "server/fleet/map_id.hpp"
#include "server/fleet/order.hpp"
#include "server/fleet/order_progress.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const strata::fleet::VehicleId vehicle{"uagv", "Strata", "robot-1"};
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const strata::fleet::OrderMessage message = strata::fleet::parse_order(text, vehicle);
  if (!message.ok()) {
    if (!message.order.nodes.empty() || message.error.empty())
      __builtin_trap();  // nothing of a refused order is taken, and the refusal says why
    return 0;
  }
  const strata::fleet::Order& order = message.order;
  if (order.nodes.empty() || order.edges.size() + 1 != order.nodes.size() || !order.nodes.front().released)
    __builtin_trap();
  for (const auto& node : order.nodes) {
    if (!std::isfinite(node.position.x) || !std::isfinite(node.position.y) ||
        !strata::fleet::parse_map_id(node.position.map_id))
      __builtin_trap();  // every goal handed to the navigator is a number on a level
  }
  strata::fleet::OrderProgress progress;
  progress.start(order);
  for (const auto* next = progress.next_base_node(); next != nullptr; next = progress.next_base_node())
    progress.pass_next_node();
  if (progress.judge(order).verdict != strata::fleet::OrderVerdict::kResent)
    __builtin_trap();  // the same order again is ignored
  return 0;
}

#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/fleet/vda_messages.hpp"
#include "server/state/goal_state.hpp"

namespace strata::fleet {

/// The largest order message taken; larger ones are refused unread (a node is about 200 bytes).
inline constexpr std::size_t kMaxOrderBytes = 512 * 1024;
/// The most nodes one order message may carry (edges: one fewer).
inline constexpr std::size_t kMaxOrderNodes = 1000;

/// Where a node is (VDA 5050 2.1, 6.6 nodePosition): Strata drives to positions, not to node names it knows.
struct NodePosition {
  double x = 0.0;
  double y = 0.0;
  std::optional<double> theta;        ///< rad; reported back, not turned to
  double allowed_deviation_xy = 0.0;  ///< m; 0: not given
  std::string map_id;                 ///< a level's mapId: "yard.smls@0"
};

struct OrderNode {
  std::string node_id;
  std::uint32_t sequence_id = 0;
  bool released = false;
  NodePosition position;
};

struct OrderEdge {
  std::string edge_id;
  std::uint32_t sequence_id = 0;
  bool released = false;
  std::string start_node_id;
  std::string end_node_id;
};

/// An order as sent: nodes and edges alternating by sequenceId, the released ones (the base) first.
struct Order {
  std::string order_id;
  std::uint64_t update_id = 0;
  std::vector<OrderNode> nodes;
  std::vector<OrderEdge> edges;
};

/// A message on the order topic, checked whole: either it is an order this vehicle can carry out, or
/// `error_type` (validationError: not a well-formed order; orderError: one this vehicle cannot carry out,
/// VDA 5050 2.1, 6.6.4) and `error` say why, with the node, edge or action concerned in `references`.
struct OrderMessage {
  Order order;
  std::optional<std::uint64_t> header_id;
  std::string error_type;  ///< empty: taken
  std::string error;
  std::vector<std::pair<std::string, std::string>> references;
  [[nodiscard]] bool ok() const { return error_type.empty(); }
};

/// Parses and validates an order payload addressed to `vehicle`: the 2.1 order schema's fields and types,
/// at least one node and one edge fewer, sequenceIds counting up by one from node to edge to node, each
/// edge between its neighbours, the released nodes and edges first, ids unique where the spec needs them,
/// the sizes above; and what Strata can carry out: every node with a nodePosition on a mapId of the
/// map@level rule, no actions, no trajectory or corridor.
[[nodiscard]] OrderMessage parse_order(std::string_view payload, const VehicleId& vehicle);

/// The navigator's goal for a node: its x, y, and as the height its mapId's level's (the goal is planned on
/// the surface nearest that height: a node on "campus.smls@1" on the deck, not on the road below). The
/// mapId must be one of the rule's (parse_order took only those).
[[nodiscard]] GoalRequest goal_of(const NodePosition& position);

}  // namespace strata::fleet

#pragma once

#include <cstdint>
#include <deque>
#include <string>

#include "server/fleet/order.hpp"

namespace strata::fleet {

/// What the vehicle does with a well-formed order (VDA 5050 2.1, 6.6.2, Figure 8).
enum class OrderVerdict {
  kNew,      ///< a new orderId, the last order done or cancelled: take it
  kUpdate,   ///< the current orderId, a higher orderUpdateId, stitched at the base's last node: extend
  kResent,   ///< the current orderId and orderUpdateId again: ignore
  kRefused,  ///< `error_type` and `reason` say why
};

struct OrderDecision {
  OrderVerdict verdict = OrderVerdict::kRefused;
  std::string error_type;  ///< orderError, orderUpdateError
  std::string reason;
};

/// The vehicle's order and how far it got: the nodes and edges still to pass (the state's nodeStates and
/// edgeStates, base and horizon), the last node passed, and the update rules. No driving here: the vehicle
/// drives to next_base_node() and calls pass_next_node() when it is there.
class OrderProgress {
 public:
  /// Whether `incoming` is new, an update, resent or refused; changes nothing.
  [[nodiscard]] OrderDecision judge(const Order& incoming) const;
  /// Takes a new order: its first node is where the vehicle stands (trivially reachable), passed at once.
  void start(const Order& order);
  /// Stitches an update on: the horizon goes, the update's nodes after the stitching node and its edges
  /// follow the base.
  void extend(const Order& update);
  /// The next base node was reached: it (and the edge to it) leave the states; it is the last node.
  void pass_next_node();
  /// Cancelled (cancelOrder): nothing left to pass; the orderId and orderUpdateId are kept.
  void cancel();

  /// The next released node to drive to, or null (nothing left, or the base ends and the horizon waits).
  [[nodiscard]] const OrderNode* next_base_node() const;
  /// Nodes left to pass (base or horizon): the order is not finished.
  [[nodiscard]] bool running() const { return !nodes_.empty(); }
  [[nodiscard]] const std::string& order_id() const { return order_id_; }
  [[nodiscard]] std::uint64_t update_id() const { return update_id_; }
  [[nodiscard]] const std::string& last_node_id() const { return last_node_id_; }
  [[nodiscard]] std::uint32_t last_node_sequence_id() const { return last_node_sequence_id_; }
  [[nodiscard]] const std::deque<OrderNode>& nodes() const { return nodes_; }
  [[nodiscard]] const std::deque<OrderEdge>& edges() const { return edges_; }

 private:
  std::string order_id_;  ///< empty: never an order
  std::uint64_t update_id_ = 0;
  std::deque<OrderNode> nodes_;  ///< not yet passed, in order
  std::deque<OrderEdge> edges_;  ///< not yet passed, in order
  std::string last_node_id_;
  std::uint32_t last_node_sequence_id_ = 0;
  std::string base_end_id_;  ///< the base's last node: where an update must stitch on
  std::uint32_t base_end_sequence_id_ = 0;
  bool cancelled_ = false;
};

}  // namespace strata::fleet

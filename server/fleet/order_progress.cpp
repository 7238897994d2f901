#include "server/fleet/order_progress.hpp"

namespace strata::fleet {
namespace {

std::string node_name(const std::string& id, std::uint32_t sequence_id) {
  return "\"" + id.substr(0, 64) + "\" (sequenceId " + std::to_string(sequence_id) + ")";
}

}  // namespace

OrderDecision OrderProgress::judge(const Order& incoming) const {
  const auto refuse = [](const char* type, std::string reason) {
    return OrderDecision{OrderVerdict::kRefused, type, std::move(reason)};
  };
  if (order_id_.empty() || incoming.order_id != order_id_) {
    if (running()) {
      return refuse("orderError", "order \"" + order_id_.substr(0, 64) + "\" is not finished (" +
                                      std::to_string(nodes_.size()) +
                                      " nodes left): cancelOrder it first, or update it");
    }
    return {OrderVerdict::kNew, {}, {}};
  }
  if (incoming.update_id < update_id_) {
    return refuse("orderUpdateError", "orderUpdateId " + std::to_string(incoming.update_id) +
                                          " is older than the current " + std::to_string(update_id_));
  }
  if (incoming.update_id == update_id_)
    return {OrderVerdict::kResent, {}, {}};
  if (cancelled_)
    return refuse("orderUpdateError", "the order was cancelled: send a new orderId");
  const OrderNode& stitch = incoming.nodes.front();
  if (stitch.node_id != base_end_id_ || stitch.sequence_id != base_end_sequence_id_) {
    return refuse("orderUpdateError",
                  "the update's first node " + node_name(stitch.node_id, stitch.sequence_id) +
                      " must be the base's last node " + node_name(base_end_id_, base_end_sequence_id_));
  }
  return {OrderVerdict::kUpdate, {}, {}};
}

void OrderProgress::start(const Order& order) {
  order_id_ = order.order_id;
  update_id_ = order.update_id;
  nodes_.assign(order.nodes.begin(), order.nodes.end());
  edges_.assign(order.edges.begin(), order.edges.end());
  cancelled_ = false;
  base_end_id_.clear();
  for (const auto& node : order.nodes) {
    if (node.released) {
      base_end_id_ = node.node_id;
      base_end_sequence_id_ = node.sequence_id;
    }
  }
  pass_next_node();  // the vehicle stands on it
}

void OrderProgress::extend(const Order& update) {
  while (!nodes_.empty() && !nodes_.back().released)
    nodes_.pop_back();
  while (!edges_.empty() && !edges_.back().released)
    edges_.pop_back();
  // The stitching node stays as the first order gave it (6.6.2: its contents do not change).
  nodes_.insert(nodes_.end(), update.nodes.begin() + 1, update.nodes.end());
  edges_.insert(edges_.end(), update.edges.begin(), update.edges.end());
  update_id_ = update.update_id;
  for (const auto& node : update.nodes) {
    if (node.released) {
      base_end_id_ = node.node_id;
      base_end_sequence_id_ = node.sequence_id;
    }
  }
}

void OrderProgress::pass_next_node() {
  if (nodes_.empty() || !nodes_.front().released)
    return;
  last_node_id_ = nodes_.front().node_id;
  last_node_sequence_id_ = nodes_.front().sequence_id;
  nodes_.pop_front();
  if (!edges_.empty() && edges_.front().sequence_id < last_node_sequence_id_)
    edges_.pop_front();
}

void OrderProgress::cancel() {
  nodes_.clear();
  edges_.clear();
  cancelled_ = true;
}

const OrderNode* OrderProgress::next_base_node() const {
  return !nodes_.empty() && nodes_.front().released ? &nodes_.front() : nullptr;
}

}  // namespace strata::fleet

#include "server/fleet/vda_vehicle.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/registration/fault_check.hpp"
#include "server/fleet/map_fetch.hpp"
#include "server/fleet/map_id.hpp"
#include "server/fleet/order.hpp"

namespace strata::fleet {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr auto kStateHeartbeat = std::chrono::seconds(30);  // VDA 5050 2.1, 6.10: at least every 30 s
constexpr std::size_t kActionStatesKept = 32;
/// How near a new order's first node the vehicle must stand when the node gives no allowedDeviationXY
/// (VDA 5050 2.1, 6.6.1: the first node is trivially reachable), m.
constexpr double kFirstNodeReach = 0.5;

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0')
    return "strata";
  return name;
}

/// A topic level from the options: no MQTT wildcards or separators.
std::string topic_level(const std::string& value, const char* option) {
  if (value.empty() || value.size() > 128 || value.find_first_of("/+#") != std::string::npos)
    throw std::runtime_error(std::string("--") + option + " must be 1-128 characters without / + #");
  return value;
}

VehicleId vehicle_id(const FleetOptions& options) {
  return {topic_level(options.interface_name, "vda5050-interface"),
          topic_level(options.manufacturer, "vda5050-manufacturer"),
          topic_level(options.serial_number.empty() ? host_name() : options.serial_number, "vda5050-serial")};
}

BrokerAddress broker_of(const FleetOptions& options) {
  std::string error;
  const auto broker = parse_broker_url(options.broker, &error);
  if (!broker)
    throw std::runtime_error("--vda5050 " + options.broker + ": " + error);
  return *broker;
}

bool goal_active(const GoalStatus& goal) {
  return goal.id != 0 && (goal.phase == GoalPhase::kAccepted || goal.phase == GoalPhase::kPlanning ||
                          goal.phase == GoalPhase::kDriving);
}

double wrap_angle(double angle) {
  return std::remainder(angle, 2.0 * std::numbers::pi);
}

/// What in a state counts as a change worth a message: everything but the pose and the velocity
/// (visualization carries those at the pose rate) and the header.
json change_relevant(json body) {
  if (const auto position = body.find("agvPosition"); position != body.end()) {
    for (const char* moving : {"x", "y", "theta", "localizationScore", "deviationRange"})
      position->erase(moving);
  }
  body.erase("velocity");
  return body;
}

}  // namespace

VdaVehicle::VdaVehicle(boost::asio::io_context& io, const ServerServices& services)
    : services_(services),
      id_(vehicle_id(services.network.fleet)),
      strand_(boost::asio::make_strand(io)),
      poll_timer_(strand_),
      poll_period_(std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(1.0 / std::clamp(services.network.pose_rate, 1.0, 100.0)))) {
  const FleetOptions& options = services.network.fleet;
  MqttSession session;
  session.client_id = "strata-" + id_.serial_number;
  session.username = options.username;
  session.password = options.password;
  session.ca_file = options.ca_file.string();
  session.will_topic = id_.topic("connection");
  session.will_payload =
      connection_header_.stamp(connection_body("CONNECTIONBROKEN"), std::chrono::system_clock::now()).dump();
  MqttLink::Handlers handlers;
  handlers.connected = [this] { on_connected(); };
  handlers.message = [this](std::string_view topic, std::string_view payload) { on_message(topic, payload); };
  link_ = std::make_shared<MqttLink>(strand_, broker_of(options), session, std::move(handlers));
}

void VdaVehicle::start() {
  spdlog::info("VDA 5050: vehicle {}/v2/{}/{} on {}", id_.interface_name, id_.manufacturer, id_.serial_number,
               services_.network.fleet.broker);
  link_->start();
  boost::asio::post(strand_, [self = shared_from_this()] { self->poll(); });
}

void VdaVehicle::close() {
  poll_timer_.cancel();
  map_thread_.stop();  // a map action under way finishes (a download within its timeout)
  map_thread_.join();
  link_->close(id_.topic("connection"),
               connection_header_.stamp(connection_body("OFFLINE"), std::chrono::system_clock::now()).dump(),
               std::chrono::seconds(1));
}

void VdaVehicle::on_connected() {
  link_->subscribe(id_.topic("instantActions"), 0);
  link_->subscribe(id_.topic("order"), 0);
  publish("connection", connection_body("ONLINE"), 1, true);
  publish_factsheet();
  publish_state(report());  // the whole state again: the master may have missed changes meanwhile
}

void VdaVehicle::on_message(std::string_view topic, std::string_view payload) {
  if (topic == id_.topic("instantActions")) {
    on_instant_actions(payload);
  } else if (topic == id_.topic("order")) {
    on_order(payload);
  }
}

void VdaVehicle::on_order(std::string_view payload) {
  const OrderMessage message = parse_order(payload, id_);
  const Order& order = message.order;
  message_errors_.clear();
  const auto refuse = [&](const std::string& type, const std::string& why,
                          const std::vector<std::pair<std::string, std::string>>& references) {
    spdlog::warn("VDA 5050: order {} refused: {}", order.order_id.substr(0, 64), why);
    VehicleError error{type, "WARNING", "order refused, nothing changed: " + why, {{"topic", "order"}}};
    if (message.header_id)
      error.references.emplace_back("headerId", std::to_string(*message.header_id));
    if (!order.order_id.empty()) {
      error.references.emplace_back("orderId", order.order_id);
      error.references.emplace_back("orderUpdateId", std::to_string(order.update_id));
    }
    error.references.insert(error.references.end(), references.begin(), references.end());
    message_errors_.push_back(std::move(error));
  };
  if (!message.ok())
    return refuse(message.error_type, message.error, message.references);
  const OrderDecision decision = order_.judge(order);
  if (decision.verdict == OrderVerdict::kResent)
    return;  // VDA 5050 2.1, 6.6.4.3: the same order again is ignored
  if (decision.verdict == OrderVerdict::kRefused)
    return refuse(decision.error_type, decision.reason, {});
  std::string node_id;
  if (const std::string why = undrivable(order, decision.verdict == OrderVerdict::kNew, &node_id);
      !why.empty())
    return refuse("orderError", why, {{"nodeId", node_id}});
  order_errors_.clear();
  order_stopped_ = false;
  if (decision.verdict == OrderVerdict::kNew) {
    order_goal_.reset();
    order_.start(order);
  } else {
    order_.extend(order);
  }
  spdlog::info("VDA 5050: order {} update {}: {} nodes to pass", order.order_id.substr(0, 64),
               order.update_id, order_.nodes().size());
  drive_order();
}

std::string VdaVehicle::undrivable(const Order& order, bool first_node_here, std::string* node_id) const {
  if (services_.motion == nullptr)
    return "this vehicle takes no goals";
  const auto map = services_.map != nullptr ? services_.map->snapshot() : nullptr;
  const std::string in_use = map != nullptr && !map->name.empty() ? map->name : std::string(kUnsavedMapName);
  for (const auto& node : order.nodes) {
    *node_id = node.node_id;
    const auto level = parse_map_id(node.position.map_id);  // the parser took only mapIds of the rule
    if (level && level->map_name != in_use)
      return "node \"" + node.node_id.substr(0, 64) + "\" is on the map \"" + level->map_name +
             "\"; the vehicle uses \"" + in_use + "\"";
  }
  if (!first_node_here)
    return {};
  const OrderNode& first = order.nodes.front();
  *node_id = first.node_id;
  const auto robot = services_.robot != nullptr ? services_.robot->snapshot() : std::nullopt;
  if (!robot || !robot->localized ||
      services_.robot->registration().localization.state == LocalizationState::kLost)
    return "the vehicle does not know where it is, so not whether it stands on the first node";
  const double reach =
      first.position.allowed_deviation_xy > 0.0 ? first.position.allowed_deviation_xy : kFirstNodeReach;
  const double distance = std::hypot(first.position.x - robot->estimate.position.x(),
                                     first.position.y - robot->estimate.position.y());
  const int level = parse_map_id(first.position.map_id)->level;
  if (distance > reach || level != level_of(robot->estimate.position.z())) {
    return fmt::format(
        "the first node is {:.2f} m from the vehicle (level {}, the vehicle on {}); it must be where the "
        "vehicle stands, within {:.2f} m (VDA 5050 2.1, 6.6.1)",
        distance, level, level_of(robot->estimate.position.z()), reach);
  }
  return {};
}

void VdaVehicle::drive_order() {
  if (!order_.running() || order_stopped_ || paused_ || services_.motion == nullptr)
    return;
  const OrderNode* next = order_.next_base_node();
  if (order_goal_ && next != nullptr) {
    const GoalStatus goal = services_.motion->goal_status();
    if (goal.id != *order_goal_) {
      return stop_order("orderError",
                        "the order's goal was replaced on the vehicle (a goal from the web app or REST)",
                        next->node_id);
    }
    switch (goal.phase) {
      case GoalPhase::kAccepted:
      case GoalPhase::kPlanning:
      case GoalPhase::kDriving:
        return;
      case GoalPhase::kFailed:
        return stop_order("NODE_UNREACHABLE",
                          "node \"" + next->node_id.substr(0, 64) + "\" cannot be reached: " + goal.message +
                              " (" + goal.reason + ")",
                          next->node_id);
      case GoalPhase::kCancelled:
        return stop_order(
            "orderError",
            "the order's goal was stopped on the vehicle" +
                (goal.message.empty() ? std::string(" (Stop or teleoperation)") : ": " + goal.message),
            next->node_id);
      case GoalPhase::kReached:
        spdlog::info("VDA 5050: order {}: node {} reached", order_.order_id().substr(0, 64),
                     next->node_id.substr(0, 64));
        order_.pass_next_node();
        order_goal_.reset();
        next = order_.next_base_node();
        break;
    }
  }
  if (next == nullptr)
    return;  // finished, or the base ends and the horizon waits for an update
  const CommandResult result = services_.motion->set_goal(goal_of(next->position));
  if (!result.ok)
    return stop_order("NODE_UNREACHABLE", "node \"" + next->node_id.substr(0, 64) + "\": " + result.message,
                      next->node_id);
  order_goal_ = result.goal_id;
}

void VdaVehicle::stop_order(std::string type, std::string why, const std::string& node_id) {
  spdlog::warn("VDA 5050: order {} stopped: {}", order_.order_id().substr(0, 64), why);
  order_stopped_ = true;
  order_goal_.reset();
  order_errors_ = {{std::move(type),
                    "WARNING",
                    std::move(why),
                    {{"topic", "order"},
                     {"orderId", order_.order_id()},
                     {"orderUpdateId", std::to_string(order_.update_id())},
                     {"nodeId", node_id}}}};
}

void VdaVehicle::on_instant_actions(std::string_view payload) {
  InstantActionsMessage message = parse_instant_actions(payload, id_);
  message_errors_.clear();
  if (!message.ok()) {
    spdlog::warn("VDA 5050: instantActions refused: {}", message.error);
    VehicleError error{"validationError",
                       "WARNING",
                       "instantActions refused, nothing done: " + message.error,
                       {{"topic", "instantActions"}}};
    if (message.header_id)
      error.references.emplace_back("headerId", std::to_string(*message.header_id));
    if (!message.error_action.empty())
      error.references.emplace_back("actionId", message.error_action);
    message_errors_.push_back(std::move(error));
    return;
  }
  for (const auto& action : message.actions)
    run(action);
}

void VdaVehicle::run(const InstantAction& action) {
  if (action.map) {
    start_map_action(action);
    return;
  }
  record(carry_out(action));
  if (action.action_type == "factsheetRequest")
    publish_factsheet();
  if (action.action_type == "stateRequest")
    publish_state(report());
}

ActionState VdaVehicle::carry_out(const InstantAction& action) {
  ActionState state{action.action_id, action.action_type, "FINISHED", {}};
  const auto fail = [&state](std::string why) {
    state.status = "FAILED";
    state.result = std::move(why);
    return state;
  };
  if (action.action_type == "initPosition") {
    const InitPosition& position = *action.init_position;
    const auto level = parse_map_id(position.map_id);
    const auto map = services_.map != nullptr ? services_.map->snapshot() : nullptr;
    const std::string in_use =
        map != nullptr && !map->name.empty() ? map->name : std::string(kUnsavedMapName);
    if (!level)
      return fail("\"" + position.map_id.substr(0, 80) + "\" is no mapId of this vehicle (MAP@LEVEL)");
    if (level->map_name != in_use)
      return fail("the mapId names the map \"" + level->map_name + "\"; the vehicle uses \"" + in_use + "\"");
    if (services_.localization == nullptr)
      return fail("this vehicle takes no pose estimates");
    const CommandResult result = services_.localization->set_pose_estimate(
        {position.x, position.y, position.theta, level_height(level->level)});
    if (!result.ok)
      return fail(result.message);
    state.result = "searching for the vehicle near the position at the next scan";
    return state;
  }
  if (action.action_type == "cancelOrder" || action.action_type == "startPause") {
    if (services_.motion == nullptr)
      return fail("this vehicle takes no goals");
    const GoalStatus goal = services_.motion->goal_status();
    if (action.action_type == "startPause") {
      if (goal_active(goal)) {
        paused_goal_ = goal.target;
        services_.motion->cancel_goal();
      }
      paused_ = true;
      return state;
    }
    if (order_.running()) {
      // The order's nodes and edges go; its ids stay (VDA 5050 2.1, 6.6.3).
      order_.cancel();
      order_goal_.reset();
      order_stopped_ = false;
      paused_goal_.reset();
      if (goal_active(goal))
        services_.motion->cancel_goal();
      return state;
    }
    if (!goal_active(goal) && !paused_goal_) {
      message_errors_.push_back({"noOrderToCancel",
                                 "WARNING",
                                 "there is no goal to cancel",
                                 {{"topic", "instantActions"}, {"actionId", action.action_id}}});
      return fail("there is no goal to cancel");
    }
    paused_goal_.reset();
    if (goal_active(goal))
      services_.motion->cancel_goal();
    return state;
  }
  if (action.action_type == "stopPause") {
    paused_ = false;
    if (paused_goal_ && services_.motion != nullptr) {
      const GoalRequest goal = *paused_goal_;
      paused_goal_.reset();
      const CommandResult result = services_.motion->set_goal(goal);
      if (!result.ok)
        return fail("the paused goal could not be taken up again: " + result.message);
      if (order_goal_)
        order_goal_ = result.goal_id;  // the order's goal goes on under its new id
    }
    return state;
  }
  return state;  // factsheetRequest, stateRequest: run() sends them
}

void VdaVehicle::start_map_action(const InstantAction& action) {
  record({action.action_id, action.action_type, "RUNNING", {}});
  boost::asio::post(map_thread_, [self = shared_from_this(), action] {
    ActionState done = self->carry_out_map_action(action);
    boost::asio::post(self->strand_, [self, done = std::move(done)]() mutable {
      self->record(std::move(done));
      self->refresh_stored_maps();
    });
  });
}

ActionState VdaVehicle::carry_out_map_action(const InstantAction& action) const {
  ActionState state{action.action_id, action.action_type, "FINISHED", {}};
  const auto fail = [&state](std::string why) {
    state.status = "FAILED";
    state.result = std::move(why);
    spdlog::warn("VDA 5050: {} {} failed: {}", state.action_type, state.action_id, state.result);
    return state;
  };
  if (services_.maps == nullptr)
    return fail("this vehicle keeps no maps");
  const MapAction& map = *action.map;
  CommandResult result;
  if (action.action_type == "downloadMap") {
    const auto started = Clock::now();
    const FetchResult fetched = fetch_url(map.download_link);
    if (!fetched.ok())
      return fail("the download failed, nothing changed: " + fetched.error);
    result = services_.maps->add_map_version(map.map_name, map.map_version, fetched.body, map.hash);
    if (!result.ok)
      return fail("the map was not stored, nothing changed: " + result.message);
    const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
    spdlog::info("VDA 5050: map {} version {} downloaded and stored in {:.3f} s ({} bytes)", map.map_name,
                 map.map_version, seconds, fetched.body.size());
    state.result = "stored, DISABLED: " + std::to_string(fetched.body.size()) + " bytes";
  } else if (action.action_type == "enableMap") {
    result = services_.maps->load_map_version(map.map_name, map.map_version, MapMode::kLocalize);
    if (!result.ok)
      return fail(result.message);
    state.result = "localizing in it: send initPosition to place the vehicle";
  } else {
    result = services_.maps->delete_map_version(map.map_name, map.map_version);
    if (!result.ok)
      return fail(result.message);
  }
  return state;
}

void VdaVehicle::refresh_stored_maps() {
  if (services_.maps != nullptr)
    stored_maps_ = services_.maps->list_map_versions();
}

void VdaVehicle::record(ActionState action) {
  const auto same = std::find_if(actions_.begin(), actions_.end(), [&action](const ActionState& known) {
    return known.action_id == action.action_id;
  });
  if (same != actions_.end())
    actions_.erase(same);
  actions_.push_back(std::move(action));
  while (actions_.size() > kActionStatesKept)
    actions_.pop_front();
}

VehicleReport VdaVehicle::report() {
  VehicleReport report;
  const auto map = services_.map != nullptr ? services_.map->snapshot() : nullptr;
  const std::string name = map != nullptr ? map->name : std::string();
  if (name != map_name_) {
    map_name_ = name;
    levels_.clear();
  }
  const auto robot = services_.robot != nullptr ? services_.robot->snapshot() : std::nullopt;
  if (robot) {
    const RegistrationStatus registration = services_.robot->registration();
    const LocalizationState health = registration.localization.state;
    const int level = level_of(robot->estimate.position.z());
    levels_.insert(level);
    AgvPosition position{robot->estimate.position.x(), robot->estimate.position.y(),
                         wrap_angle(robot->estimate.yaw), map_id(name, level),
                         robot->localized && health != LocalizationState::kLost};
    if (registration.last) {
      // How closely the scans match: 1 at a perfect fit, 0 at the RMSE fault control refuses and when lost.
      // The score's zero is where fault control refuses a match (FaultLimits::max_rmse), not a copy of it.
      double score = std::clamp(1.0 - registration.last->rmse / FaultLimits{}.max_rmse, 0.0, 1.0);
      if (health == LocalizationState::kDegraded)
        score *= 0.5;
      position.localization_score = health == LocalizationState::kLost ? 0.0 : score;
      position.deviation_range = registration.last->rmse;
    }
    report.position = position;
    if (robot->sample.velocity_known)
      report.velocity = Velocity{robot->sample.velocity.v, robot->sample.velocity.w};
    if (health == LocalizationState::kLost) {
      report.errors.push_back(
          {"LOCALIZATION_ERROR", "FATAL", "localization lost: " + registration.localization.reason, {}});
    }
    const bool moving = robot->sample.velocity_known && (std::abs(robot->sample.velocity.v) > 0.01 ||
                                                         std::abs(robot->sample.velocity.w) > 0.01);
    const bool driving_goal =
        services_.motion != nullptr && services_.motion->goal_status().phase == GoalPhase::kDriving;
    report.driving = moving || driving_goal;
  }
  // The stored versions (the map server's): the one in use ENABLED, the others DISABLED; each on the
  // levels its robot drove (and the in-use one also on those this robot stood on).
  const std::string saved_version = map != nullptr ? map->saved_version : std::string();
  if (const std::string key = name + "\n" + saved_version; key != stored_maps_key_) {
    stored_maps_key_ = key;
    refresh_stored_maps();  // a save made a version, a load took one up
  }
  bool in_use_listed = false;
  for (const auto& stored : stored_maps_) {
    const bool in_use = stored.name == name && !saved_version.empty() && stored.version == saved_version;
    std::set<int> levels;
    for (const double height : stored.heights)
      levels.insert(level_of(height));
    if (in_use)
      levels.insert(levels_.begin(), levels_.end());
    if (levels.empty())
      levels.insert(0);
    for (const int level : levels)
      report.maps.push_back({map_id(stored.name, level), stored.version, in_use});
    in_use_listed = in_use_listed || in_use;
  }
  if (!in_use_listed) {
    // While mapping the map changes with every scan ("live"); a map localized in keeps its version.
    const std::string version = map != nullptr && map->localizing ? std::to_string(map->version) : "live";
    for (const int level : levels_)
      report.maps.push_back({map_id(name, level), version, true});
  }
  report.order_id = order_.order_id();
  report.order_update_id = order_.update_id();
  report.last_node_id = order_.last_node_id();
  report.last_node_sequence_id = order_.last_node_sequence_id();
  for (const auto& node : order_.nodes()) {
    report.node_states.push_back({node.node_id, node.sequence_id, node.released, node.position.x,
                                  node.position.y, node.position.theta, node.position.map_id});
  }
  for (const auto& edge : order_.edges())
    report.edge_states.push_back({edge.edge_id, edge.sequence_id, edge.released});
  report.errors.insert(report.errors.end(), order_errors_.begin(), order_errors_.end());
  report.errors.insert(report.errors.end(), message_errors_.begin(), message_errors_.end());
  report.actions.assign(actions_.begin(), actions_.end());
  report.paused = paused_;
  return report;
}

void VdaVehicle::poll() {
  drive_order();
  const VehicleReport now = report();
  const auto robot = services_.robot != nullptr ? services_.robot->snapshot() : std::nullopt;
  if (robot && robot->version != last_pose_version_) {
    last_pose_version_ = robot->version;
    publish("visualization", visualization_body(now), 0, false);
  }
  if (change_relevant(state_body(now)) != last_state_ || Clock::now() - last_state_sent_ >= kStateHeartbeat)
    publish_state(now);
  poll_timer_.expires_after(poll_period_);
  poll_timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
    if (!error)
      self->poll();
  });
}

void VdaVehicle::publish_state(const VehicleReport& report) {
  json body = state_body(report);
  last_state_ = change_relevant(body);
  last_state_sent_ = Clock::now();
  publish("state", std::move(body), 0, false);
}

void VdaVehicle::publish_factsheet() {
  const FleetOptions& options = services_.network.fleet;
  publish("factsheet", factsheet_body({options.robot_radius, options.robot_height, options.max_speed}), 0,
          true);
}

void VdaVehicle::publish(std::string_view topic, json body, int qos, bool retain) {
  if (!link_->connected())
    return;  // on_connected() sends connection, factsheet and state again
  HeaderStamp& header = topic == "state"           ? state_header_
                        : topic == "visualization" ? visualization_header_
                        : topic == "connection"    ? connection_header_
                                                   : factsheet_header_;
  link_->publish(id_.topic(topic), header.stamp(std::move(body), std::chrono::system_clock::now()).dump(),
                 qos, retain);
}

}  // namespace strata::fleet

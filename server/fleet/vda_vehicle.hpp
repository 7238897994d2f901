#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/thread_pool.hpp>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "server/control/server_services.hpp"
#include "server/fleet/instant_actions.hpp"
#include "server/fleet/mqtt_link.hpp"
#include "server/fleet/order_progress.hpp"
#include "server/fleet/vda_messages.hpp"

namespace strata::fleet {

/// The robot as a VDA 5050 2.1 vehicle to a fleet master over MQTT (docs/fleet.md): `connection` (ONLINE,
/// OFFLINE, the broker's last will CONNECTIONBROKEN), `state` on every change and at least every 30 s,
/// `visualization` at the pose rate, the `factsheet`, and the instant actions and orders it carries out
/// through the same commands the WebSocket and REST use (an order's base: node by node as goals). Everything
/// runs on the MQTT link's strand.
class VdaVehicle : public std::enable_shared_from_this<VdaVehicle> {
 public:
  /// Checks the options (throws with what is wrong); nothing connects before start().
  VdaVehicle(boost::asio::io_context& io, const ServerServices& services);
  void start();
  /// After the event loop has stopped: connection OFFLINE, and a clean disconnect.
  void close();

 private:
  void on_connected();
  void on_message(std::string_view topic, std::string_view payload);
  void on_instant_actions(std::string_view payload);
  void on_order(std::string_view payload);
  /// Why a new order or an update cannot be driven here (a node on another map, the first node not where
  /// the vehicle stands), or empty.
  [[nodiscard]] std::string undrivable(const Order& order, bool first_node_here, std::string* node_id) const;
  /// On every poll: the order's next base node as the goal, the node passed once the goal is reached, the
  /// order stopped with the planner's reason when it is not.
  void drive_order();
  void stop_order(std::string type, std::string why, const std::string& node_id);
  void run(const InstantAction& action);
  [[nodiscard]] ActionState carry_out(const InstantAction& action);
  /// downloadMap, enableMap, deleteMap: RUNNING at once, then carried out on the map thread, one after
  /// another in the order they came (a download, then its enableMap).
  void start_map_action(const InstantAction& action);
  /// On the map thread: a download takes seconds, a load too; the link's strand goes on meanwhile.
  [[nodiscard]] ActionState carry_out_map_action(const InstantAction& action) const;
  /// The map server's versions, for state.maps (read again when they may have changed).
  void refresh_stored_maps();
  void poll();
  [[nodiscard]] VehicleReport report();
  void publish_state(const VehicleReport& report);
  void publish_factsheet();
  void publish(std::string_view topic, nlohmann::json body, int qos, bool retain);
  void record(ActionState action);

  ServerServices services_;
  VehicleId id_;
  MqttLink::Strand strand_;
  boost::asio::steady_timer poll_timer_;
  std::shared_ptr<MqttLink> link_;
  std::chrono::steady_clock::duration poll_period_;
  HeaderStamp connection_header_{id_};
  HeaderStamp state_header_{id_};
  HeaderStamp visualization_header_{id_};
  HeaderStamp factsheet_header_{id_};
  std::optional<std::uint64_t> last_pose_version_;
  nlohmann::json last_state_;  ///< what the last state said that counts as a change (no pose, no header)
  std::chrono::steady_clock::time_point last_state_sent_;
  std::deque<ActionState> actions_;           ///< the newest instant actions' states
  std::vector<VehicleError> message_errors_;  ///< from the last message received, until the next
  std::string map_name_;                      ///< of the map the levels below were seen on
  std::set<int> levels_;                      ///< the levels the robot stood on in that map
  bool paused_ = false;
  std::optional<GoalRequest> paused_goal_;  ///< the goal startPause stopped, for stopPause
  OrderProgress order_;
  std::optional<std::uint64_t> order_goal_;  ///< the goal driving to the order's next node
  bool order_stopped_ = false;               ///< a node could not be reached: waits for the master
  std::vector<VehicleError> order_errors_;   ///< why the order stopped, until the next order is taken
  std::vector<MapVersionInfo> stored_maps_;  ///< the map versions on this vehicle
  std::string stored_maps_key_;              ///< the map in use (name, version) when they were read
  boost::asio::thread_pool map_thread_{1};   ///< the map actions' thread
};

}  // namespace strata::fleet

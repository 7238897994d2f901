// REST requests: the router with its query strings, path parameters and JSON bodies (goal, map save and
// load, tile coordinates, download formats). Input: byte 0 picks the method and whether the request carries
// the operator token; then the target up to the first newline; the rest is the body. The robot's side is
// stubs that accept everything, so the parsing and validation in front of them is what runs.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "drivers/sim/world/world_file.hpp"
#include "server/api/http_router.hpp"

namespace {

namespace http = boost::beast::http;
constexpr const char* kToken = "fuzz-operator-token-0123456789";

class AcceptingMotion : public strata::MotionCommands {
 public:
  strata::CommandResult set_goal(const strata::GoalRequest&) override {
    return strata::CommandResult::success();
  }
  strata::CommandResult cancel_goal() override { return strata::CommandResult::success(); }
  bool cancel_goal_if_active(std::uint64_t, const std::string&) override { return false; }
  strata::CommandResult teleop(double, double, std::chrono::steady_clock::time_point) override {
    return strata::CommandResult::success();
  }
  void stop_teleop() override {}
  [[nodiscard]] strata::GoalStatus goal_status() const override { return {}; }
  [[nodiscard]] std::shared_ptr<const strata::PlannedPath> path() const override { return nullptr; }
};

class AcceptingMaps : public strata::MapCommands {
 public:
  strata::CommandResult save_map(const std::string&) override { return strata::CommandResult::success(); }
  strata::CommandResult load_map(const std::string&, strata::MapMode) override {
    return strata::CommandResult::success();
  }
  [[nodiscard]] std::vector<strata::MapFileInfo> list_maps() const override { return {{"known", 10, 1.0}}; }
  [[nodiscard]] strata::MapDownload download(const std::string& format,
                                             std::optional<std::uint64_t> version) const override {
    if (version && *version != 1)
      return {.version = 1, .version_gone = true};
    return {.bytes = {format.begin(), format.end()}, .version = 1};
  }
};

struct Server {
  Server() {
    strata::RobotSample sample;
    sample.stamp = 1.5;
    sample.odometry.position = {1.0, 2.0, 0.0};
    robot.publish(sample);
    services.robot = &robot;
    services.map = &map;
    services.motion = &motion;
    services.maps = &maps;
    services.sim_world = &world;
    services.network.operator_token = kToken;
    services.network.web_root = "/nonexistent-strata-fuzz-web-root";
  }
  strata::RobotState robot;
  strata::MapState map;
  AcceptingMotion motion;
  AcceptingMaps maps;
  strata::sim::World world{strata::sim::builtin_world("yard")};
  strata::ServerServices services;
  strata::streams::ClientHub hub;
  strata::streams::ServerMetrics metrics;
  strata::streams::StatusStream status{robot, &map, hub};
  strata::api::HttpRouter router{services, hub, status, metrics};
};

constexpr http::verb kMethods[] = {http::verb::get,     http::verb::post,   http::verb::put,
                                   http::verb::delete_, http::verb::head,   http::verb::options,
                                   http::verb::patch,   http::verb::connect};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Server* const server =
      new Server;  // built once; never destroyed (libFuzzer exits without unwinding)
  if (size == 0)
    return 0;
  const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  const std::size_t newline = rest.find('\n');
  const std::string_view target = rest.substr(0, newline);
  const std::string_view body =
      newline == std::string_view::npos ? std::string_view() : rest.substr(newline + 1);

  strata::protocol::HttpRequest request{kMethods[data[0] % std::size(kMethods)], target, 11};
  if ((data[0] & 0x80U) != 0)
    request.set(http::field::authorization, std::string("Bearer ") + kToken);
  request.body() = std::string(body);
  request.prepare_payload();
  try {
    const strata::protocol::HttpResponse response = server->router.handle(request);
    // The stubs never fail, so a 500 is the router's safety net catching an exception: a bug.
    if (response.result_int() < 100 || response.result() == http::status::internal_server_error)
      __builtin_trap();
  } catch (const std::invalid_argument&) {
    // Beast refuses a target with characters a request line cannot carry; never reaches the router.
  }
  return 0;
}

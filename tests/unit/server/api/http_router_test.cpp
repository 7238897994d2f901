#include "server/api/http_router.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "drivers/sim/world/world_file.hpp"
#include "server/protocol/binary_frames.hpp"

namespace strata::api {
namespace {

namespace http = protocol::http;

protocol::HttpRequest request(http::verb method, std::string target) {
  protocol::HttpRequest req{method, target, 11};
  req.prepare_payload();
  return req;
}

constexpr const char* kToken = "operator-token-0123456789";

/// Records what the router asked of the navigator (the router is tested alone; the real navigator is
/// driven end to end by the integration tests).
class RecordingMotion : public MotionCommands {
 public:
  CommandResult set_goal(const GoalRequest& goal) override {
    status.id += 1;
    status.target = goal;
    status.phase = GoalPhase::kAccepted;
    return CommandResult::success();
  }
  CommandResult cancel_goal() override {
    status.phase = GoalPhase::kCancelled;
    return CommandResult::success();
  }
  bool cancel_goal_if_active(std::uint64_t, const std::string&) override { return false; }
  CommandResult teleop(double, double, std::chrono::steady_clock::time_point) override {
    return CommandResult::success();
  }
  void stop_teleop() override {}
  [[nodiscard]] GoalStatus goal_status() const override { return status; }
  [[nodiscard]] std::shared_ptr<const PlannedPath> path() const override { return nullptr; }
  GoalStatus status;
};

class RecordingMaps : public MapCommands {
 public:
  CommandResult save_map(const std::string& name) override {
    saved.push_back(name);
    return CommandResult::success();
  }
  CommandResult load_map(const std::string& name, MapMode mode) override {
    loaded.push_back(name);
    modes.push_back(mode);
    if (name != "known")
      return CommandResult::failure(ErrorCode::kNotFound, "no map named " + name);
    return CommandResult::success();
  }
  [[nodiscard]] std::vector<MapFileInfo> list_maps() const override { return {{"known", 10, 1.0}}; }
  /// The format's name as the bytes, at map version 7, which is also the only one kept.
  [[nodiscard]] MapDownload download(const std::string& format,
                                     std::optional<std::uint64_t> version) const override {
    if (version && *version != 7)
      return {.version = 7, .version_gone = true};
    return {.bytes = {format.begin(), format.end()}, .version = 7};
  }
  std::vector<std::string> saved;
  std::vector<std::string> loaded;
  std::vector<MapMode> modes;
};

ServerServices services_for(const RobotState& robot, const MapState& map, MotionCommands& motion,
                            MapCommands& maps, const sim::World& world) {
  ServerServices services;
  services.robot = &robot;
  services.map = &map;
  services.motion = &motion;
  services.maps = &maps;
  services.sim_world = &world;
  services.network.operator_token = kToken;
  services.network.web_root = "/nonexistent-web-root";
  return services;
}

class Router : public ::testing::Test {
 protected:
  protocol::HttpRequest operator_request(http::verb method, std::string target, std::string body = {}) {
    auto req = request(method, std::move(target));
    req.set(http::field::authorization, std::string("Bearer ") + kToken);
    req.body() = std::move(body);
    req.prepare_payload();
    return req;
  }

  RobotState robot_;
  MapState map_;
  RecordingMotion motion_;
  RecordingMaps maps_;
  sim::World world_{sim::builtin_world("yard")};
  ServerServices services_ = services_for(robot_, map_, motion_, maps_, world_);
  streams::ClientHub hub_;
  streams::ServerMetrics metrics_;
  streams::StatusStream status_{robot_, &map_, hub_};
  HttpRouter router_{services_, hub_, status_, metrics_};
};

TEST_F(Router, HealthAndInfo) {
  auto health = router_.handle(request(http::verb::get, "/healthz"));
  EXPECT_EQ(health.result(), http::status::ok);
  auto info = router_.handle(request(http::verb::get, "/api/v1/info"));
  ASSERT_EQ(info.result(), http::status::ok);
  const auto body = nlohmann::json::parse(info.body());
  EXPECT_EQ(body["name"], "strata");
  EXPECT_EQ(body["protocol"], "strata.v1");
  EXPECT_EQ(body["protocol_version"], 1);
  EXPECT_EQ(info[http::field::content_type], "application/json");
}

TEST_F(Router, PoseIsUnavailableUntilTheRobotReports) {
  auto before = router_.handle(request(http::verb::get, "/api/v1/pose"));
  EXPECT_EQ(before.result(), http::status::service_unavailable);
  EXPECT_EQ(nlohmann::json::parse(before.body())["error"]["code"], "unavailable");

  RobotSample sample;
  sample.stamp = 1.5;
  sample.odometry.position = {1.0, 2.0, 0.0};
  sample.odometry.yaw = 0.5;
  robot_.publish(sample);
  auto after = router_.handle(request(http::verb::get, "/api/v1/pose?x=1"));
  ASSERT_EQ(after.result(), http::status::ok);
  const auto pose = nlohmann::json::parse(after.body());
  EXPECT_DOUBLE_EQ(pose["x"], 1.0);
  EXPECT_DOUBLE_EQ(pose["y"], 2.0);
  EXPECT_DOUBLE_EQ(pose["yaw"], 0.5);
  EXPECT_DOUBLE_EQ(pose["stamp"], 1.5);
  for (const char* key : {"z", "roll", "pitch", "frame"})
    EXPECT_TRUE(pose.contains(key)) << key;
}

TEST_F(Router, UnknownEndpointsAndMethodsGetCodedErrors) {
  auto missing = router_.handle(request(http::verb::get, "/api/v1/nope"));
  EXPECT_EQ(missing.result(), http::status::not_found);
  EXPECT_EQ(nlohmann::json::parse(missing.body())["error"]["code"], "not_found");

  auto post = router_.handle(request(http::verb::post, "/api/v1/info"));
  EXPECT_EQ(post.result(), http::status::method_not_allowed);
  EXPECT_EQ(post[http::field::allow], "GET, HEAD");
  EXPECT_EQ(nlohmann::json::parse(post.body())["error"]["code"], "method_not_allowed");
}

TEST_F(Router, HeadHasHeadersButNoBody) {
  auto head = router_.handle(request(http::verb::head, "/api/v1/info"));
  EXPECT_EQ(head.result(), http::status::ok);
  EXPECT_TRUE(head.body().empty());
  EXPECT_NE(head[http::field::content_length], "0");
}

TEST_F(Router, SimWorldIsServed) {
  auto world = router_.handle(request(http::verb::get, "/api/v1/sim/world"));
  ASSERT_EQ(world.result(), http::status::ok);
  EXPECT_EQ(nlohmann::json::parse(world.body())["name"], "yard");
}

TEST_F(Router, ControlNeedsTheOperatorToken) {
  auto anonymous = request(http::verb::post, "/api/v1/goal");
  anonymous.body() = R"({"x":1,"y":2})";
  anonymous.prepare_payload();
  auto refused = router_.handle(anonymous);
  EXPECT_EQ(refused.result(), http::status::unauthorized);
  EXPECT_EQ(nlohmann::json::parse(refused.body())["error"]["code"], "unauthorized");
  EXPECT_FALSE(refused[http::field::www_authenticate].empty());
  EXPECT_EQ(motion_.status.id, 0u);  // nothing changed

  auto wrong = anonymous;
  wrong.set(http::field::authorization, "Bearer operator-token-0123456780");
  EXPECT_EQ(router_.handle(wrong).result(), http::status::unauthorized);
  EXPECT_EQ(motion_.status.id, 0u);

  auto accepted =
      router_.handle(operator_request(http::verb::post, "/api/v1/goal", R"({"x":1,"y":2,"z":0.5})"));
  ASSERT_EQ(accepted.result(), http::status::accepted) << accepted.body();
  const auto goal = nlohmann::json::parse(accepted.body());
  EXPECT_EQ(goal["phase"], "accepted");
  EXPECT_DOUBLE_EQ(goal["z"], 0.5);
  EXPECT_EQ(motion_.status.id, 1u);

  // Anyone may read the goal.
  auto read = router_.handle(request(http::verb::get, "/api/v1/goal"));
  EXPECT_EQ(read.result(), http::status::ok);
  EXPECT_EQ(nlohmann::json::parse(read.body())["id"], 1);
}

TEST_F(Router, TheCookieCountsOnlyFromTheServersOwnOrigin) {
  auto with_cookie = request(http::verb::delete_, "/api/v1/goal");
  with_cookie.set(http::field::cookie, std::string("theme=dark; strata_token=") + kToken);
  with_cookie.set(http::field::host, "robot.local:8080");
  with_cookie.set(http::field::origin, "http://evil.example");
  EXPECT_EQ(router_.handle(with_cookie).result(), http::status::unauthorized);
  with_cookie.set(http::field::origin, "http://robot.local:8080");
  EXPECT_EQ(router_.handle(with_cookie).result(), http::status::ok);
  EXPECT_EQ(motion_.status.phase, GoalPhase::kCancelled);
}

TEST_F(Router, BadGoalsAreRefusedWithCodes) {
  for (const char* body : {"not json", "[1,2]", R"({"x":1})", R"({"x":"1","y":2})", R"({"x":1,"y":2,"w":3})",
                           R"({"x":1e9,"y":2})"}) {
    auto response = router_.handle(operator_request(http::verb::post, "/api/v1/goal", body));
    EXPECT_EQ(response.result(), http::status::bad_request) << body;
    const auto code = nlohmann::json::parse(response.body())["error"]["code"];
    EXPECT_TRUE(code == "bad_json" || code == "bad_params") << body << " -> " << code;
  }
  EXPECT_EQ(motion_.status.id, 0u);
}

TEST_F(Router, TilesHaveETagsAndAnswer304) {
  auto snapshot = std::make_shared<MapSnapshot>();
  snapshot->version = 7;
  snapshot->tiles.push_back(std::make_shared<EncodedTile>(EncodedTile{2, -3, 7, 4, {1, 2, 3, 4, 5}}));
  map_.publish(snapshot);

  const auto index = nlohmann::json::parse(router_.handle(request(http::verb::get, "/api/v1/tiles")).body());
  ASSERT_EQ(index["tiles"].size(), 1u);
  EXPECT_EQ(index["tiles"][0]["x"], 2);
  EXPECT_EQ(index["tiles"][0]["y"], -3);

  auto tile = router_.handle(request(http::verb::get, "/api/v1/tiles/2/-3"));
  ASSERT_EQ(tile.result(), http::status::ok);
  const std::string etag(tile[http::field::etag]);
  EXPECT_EQ(etag, index["tiles"][0]["etag"]);
  const std::span bytes(reinterpret_cast<const std::uint8_t*>(tile.body().data()), tile.body().size());
  const auto decoded = protocol::decode_tile_frame(bytes);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->version, 7u);
  EXPECT_EQ(decoded->draco, (std::vector<std::uint8_t>{1, 2, 3, 4, 5}));

  auto again = request(http::verb::get, "/api/v1/tiles/2/-3");
  again.set(http::field::if_none_match, etag);
  auto not_modified = router_.handle(again);
  EXPECT_EQ(not_modified.result(), http::status::not_modified);
  EXPECT_TRUE(not_modified.body().empty());

  EXPECT_EQ(router_.handle(request(http::verb::get, "/api/v1/tiles/9/9")).result(), http::status::not_found);
  EXPECT_EQ(router_.handle(request(http::verb::get, "/api/v1/tiles/a/b")).result(), http::status::not_found);
}

TEST_F(Router, OccupancyIsAPngWithItsPlaceInTheMap) {
  EXPECT_EQ(router_.handle(request(http::verb::get, "/api/v1/occupancy")).result(),
            http::status::service_unavailable);
  auto snapshot = std::make_shared<MapSnapshot>();
  auto image = std::make_shared<EncodedOccupancy>();
  image->version = 3;
  image->origin_x = -1.5;
  image->origin_y = 2.0;
  image->resolution = 0.1;
  image->png = {0x89, 'P', 'N', 'G'};
  snapshot->occupancy = image;
  map_.publish(snapshot);
  auto response = router_.handle(request(http::verb::get, "/api/v1/occupancy"));
  ASSERT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(response[http::field::content_type], "image/png");
  EXPECT_EQ(response["X-Strata-Origin"], "-1.5,2");
  EXPECT_EQ(response["X-Strata-Resolution"], "0.1");
}

TEST_F(Router, MapDownloadsAndSavedMaps) {
  auto ply = router_.handle(request(http::verb::get, "/api/v1/map?format=ply"));
  ASSERT_EQ(ply.result(), http::status::ok);
  EXPECT_EQ(ply.body(), "ply");
  EXPECT_NE(std::string(ply[http::field::content_disposition]).find("map.ply"), std::string::npos);
  EXPECT_EQ(router_.handle(request(http::verb::get, "/api/v1/map")).body(), "strata");
  EXPECT_EQ(router_.handle(request(http::verb::get, "/api/v1/map?format=exe")).result(),
            http::status::bad_request);
  // The ROS map by the version its YAML named; another is gone; a version that is no number is refused.
  auto yaml = router_.handle(request(http::verb::get, "/api/v1/map?format=yaml"));
  EXPECT_EQ(yaml["X-Strata-Version"], "7");
  auto pgm = router_.handle(request(http::verb::get, "/api/v1/map?format=pgm&version=7"));
  ASSERT_EQ(pgm.result(), http::status::ok);
  EXPECT_EQ(pgm.body(), "pgm");
  auto gone = router_.handle(request(http::verb::get, "/api/v1/map?format=pgm&version=6"));
  EXPECT_EQ(gone.result(), http::status::gone);
  EXPECT_NE(gone.body().find("map version 6 is gone (the map is at version 7)"), std::string::npos)
      << gone.body();
  EXPECT_EQ(router_.handle(request(http::verb::get, "/api/v1/map?format=pgm&version=7x")).result(),
            http::status::bad_request);

  // Anyone may list the saved maps; a token offered and wrong is refused (the page checks tokens so).
  auto viewer_list = router_.handle(request(http::verb::get, "/api/v1/maps"));
  ASSERT_EQ(viewer_list.result(), http::status::ok);
  EXPECT_EQ(nlohmann::json::parse(viewer_list.body())["maps"][0]["name"], "known");
  auto list = router_.handle(operator_request(http::verb::get, "/api/v1/maps"));
  ASSERT_EQ(list.result(), http::status::ok);
  auto wrong = request(http::verb::get, "/api/v1/maps");
  wrong.set(http::field::authorization, "Bearer not-the-token");
  EXPECT_EQ(router_.handle(wrong).result(), http::status::unauthorized);
  // Saving and loading stay the operator's.
  EXPECT_EQ(router_.handle(request(http::verb::post, "/api/v1/maps/known/load")).result(),
            http::status::unauthorized);
  // Another scheme than Bearer is told which to use.
  auto scheme = request(http::verb::post, "/api/v1/goal");
  scheme.set(http::field::authorization, std::string("Token ") + kToken);
  const auto refused = router_.handle(scheme);
  EXPECT_EQ(refused.result(), http::status::unauthorized);
  EXPECT_NE(refused.body().find("Authorization: Bearer <token>"), std::string::npos) << refused.body();

  EXPECT_EQ(router_.handle(operator_request(http::verb::post, "/api/v1/maps", R"({"name":"../etc/passwd"})"))
                .result(),
            http::status::bad_request);
  EXPECT_TRUE(maps_.saved.empty());
  EXPECT_EQ(router_.handle(operator_request(http::verb::post, "/api/v1/maps", R"({"name":"hall.strata"})"))
                .result(),
            http::status::created);
  EXPECT_EQ(maps_.saved, (std::vector<std::string>{"hall.strata"}));
  EXPECT_EQ(router_.handle(operator_request(http::verb::post, "/api/v1/maps/known/load")).result(),
            http::status::ok);
  EXPECT_EQ(router_.handle(operator_request(http::verb::post, "/api/v1/maps/other/load")).result(),
            http::status::not_found);
  EXPECT_EQ(maps_.loaded, (std::vector<std::string>{"known", "other"}));
  // The mode: mapping unless the body says localize; anything else is refused before the map is touched.
  const auto localized =
      router_.handle(operator_request(http::verb::post, "/api/v1/maps/known/load", R"({"mode":"localize"})"));
  EXPECT_EQ(localized.result(), http::status::ok);
  EXPECT_EQ(nlohmann::json::parse(localized.body())["mode"], "localize");
  EXPECT_EQ(maps_.modes, (std::vector<MapMode>{MapMode::kMapping, MapMode::kMapping, MapMode::kLocalize}));
  for (const char* body :
       {R"({"mode":"navigate"})", R"({"mode":1})", R"({"name":"x"})", "[", R"("localize")"}) {
    EXPECT_EQ(router_.handle(operator_request(http::verb::post, "/api/v1/maps/known/load", body)).result(),
              http::status::bad_request)
        << body;
  }
  EXPECT_EQ(maps_.loaded.size(), 3U);
}

// "/api/v1/maps/load" names no map: the name's length was computed as 5 - 1 - 5 (wrapping), so it loaded a
// map called "load".
TEST_F(Router, LoadWithoutAMapNameIsNotFound) {
  EXPECT_EQ(router_.handle(operator_request(http::verb::post, "/api/v1/maps/load")).result(),
            http::status::not_found);
  EXPECT_TRUE(maps_.loaded.empty());
}

TEST_F(Router, MetricsArePrometheusText) {
  auto response = router_.handle(request(http::verb::get, "/metrics"));
  ASSERT_EQ(response.result(), http::status::ok);
  EXPECT_NE(response.body().find("# TYPE strata_ws_clients gauge\nstrata_ws_clients 0\n"), std::string::npos);
  EXPECT_NE(response.body().find("strata_scans_total 0"), std::string::npos);
  // The localization state, one series per state: 1 for the current one (no scan yet: degraded).
  EXPECT_NE(response.body().find("# TYPE strata_localization_state gauge\n"
                                 "strata_localization_state{state=\"ok\"} 0\n"
                                 "strata_localization_state{state=\"degraded\"} 1\n"
                                 "strata_localization_state{state=\"lost\"} 0\n"),
            std::string::npos)
      << response.body();
  RegistrationStatus lost;
  lost.localization = {LocalizationState::kLost, "no scan matched"};
  robot_.set_registration(lost);
  const std::string body = router_.handle(request(http::verb::get, "/metrics")).body();
  EXPECT_NE(body.find("strata_localization_state{state=\"lost\"} 1\n"), std::string::npos) << body;
  EXPECT_NE(body.find("strata_localization_state{state=\"degraded\"} 0\n"), std::string::npos) << body;
}

TEST_F(Router, StaticFilesOutsideTheApiAre404WithoutABundle) {
  auto page = router_.handle(request(http::verb::get, "/"));
  EXPECT_EQ(page.result(), http::status::not_found);
}

}  // namespace
}  // namespace strata::api

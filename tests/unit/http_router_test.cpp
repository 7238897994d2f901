#include "server/api/http_router.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace strata::api {
namespace {

namespace http = net::http;

net::HttpRequest request(http::verb method, std::string target) {
  net::HttpRequest req{method, target, 11};
  req.prepare_payload();
  return req;
}

class Router : public ::testing::Test {
 protected:
  RobotState robot_;
  net::ClientHub hub_;
  HttpRouter router_{robot_, hub_, "/nonexistent-web-root", R"({"name":"w","boxes":[]})"};
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

  sim::RobotSample sample;
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
  EXPECT_EQ(nlohmann::json::parse(world.body())["name"], "w");
}

TEST_F(Router, StaticFilesOutsideTheApiAre404WithoutABundle) {
  auto page = router_.handle(request(http::verb::get, "/"));
  EXPECT_EQ(page.result(), http::status::not_found);
}

}  // namespace
}  // namespace strata::api

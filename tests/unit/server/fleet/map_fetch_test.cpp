// downloadMap's links (issue 61): http and https URLs split into host, port and target; anything else
// refused with the reason.
#include "server/fleet/map_fetch.hpp"

#include <gtest/gtest.h>

#include <string>

namespace strata::fleet {
namespace {

TEST(MapFetch, LinksSplitIntoHostPortAndTarget) {
  auto url = parse_http_url("http://robot-a:8080/api/v1/maps/yard.smls/versions/1");
  ASSERT_TRUE(url);
  EXPECT_FALSE(url->tls);
  EXPECT_EQ(url->host, "robot-a");
  EXPECT_EQ(url->port, 8080);
  EXPECT_EQ(url->target, "/api/v1/maps/yard.smls/versions/1");
  url = parse_http_url("https://maps.example.org?v=2#part");
  ASSERT_TRUE(url);
  EXPECT_TRUE(url->tls);
  EXPECT_EQ(url->port, 443);
  EXPECT_EQ(url->target, "/?v=2");
  url = parse_http_url("http://[::1]:81/m");
  ASSERT_TRUE(url);
  EXPECT_EQ(url->host, "::1");
  EXPECT_EQ(url->port, 81);
}

TEST(MapFetch, OtherLinksAreRefusedWithTheReason) {
  std::string error;
  EXPECT_FALSE(parse_http_url("ftp://host/m", &error));
  EXPECT_NE(error.find("http://"), std::string::npos) << error;
  EXPECT_FALSE(parse_http_url("http://host:99999/m", &error));
  EXPECT_NE(error.find("port"), std::string::npos) << error;
  EXPECT_FALSE(parse_http_url("http://user@host/m", &error));
  EXPECT_FALSE(parse_http_url("http:///m", &error));
}

TEST(MapFetch, AnUnreachableServerIsAnErrorNotAHang) {
  // Port 1 on loopback: nothing listens, the connection is refused at once.
  const FetchResult result =
      fetch_url("http://127.0.0.1:1/m", {.max_bytes = 1024, .timeout = std::chrono::seconds(5)});
  EXPECT_FALSE(result.ok());
  EXPECT_TRUE(result.body.empty());
}

}  // namespace
}  // namespace strata::fleet

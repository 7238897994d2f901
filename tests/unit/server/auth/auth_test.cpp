#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "server/auth/operator_token.hpp"
#include "server/auth/request_auth.hpp"

namespace strata::auth {
namespace {

namespace http = protocol::http;
constexpr std::string_view kToken = "Sesame-0123456789_abc";

protocol::HttpRequest upgrade(std::string protocols = {}) {
  protocol::HttpRequest request{http::verb::get, "/ws", 11};
  request.set(http::field::host, "robot:8080");
  if (!protocols.empty())
    request.set(http::field::sec_websocket_protocol, protocols);
  return request;
}

TEST(OperatorToken, ConstantTimeEqualIsEquality) {
  EXPECT_TRUE(constant_time_equal("abc", "abc"));
  EXPECT_FALSE(constant_time_equal("abd", "abc"));
  EXPECT_FALSE(constant_time_equal("ab", "abc"));
  EXPECT_FALSE(constant_time_equal("abcd", "abc"));
  EXPECT_FALSE(constant_time_equal("", "abc"));
  EXPECT_TRUE(constant_time_equal("", ""));
}

TEST(OperatorToken, GeneratedTokensAreValidAndDistinct) {
  std::set<std::string> seen;
  for (int i = 0; i < 50; ++i) {
    const auto token = generate_token();
    EXPECT_EQ(token.size(), 32u);
    EXPECT_TRUE(is_valid_token(token)) << token;
    seen.insert(token);
  }
  EXPECT_EQ(seen.size(), 50u);
  EXPECT_FALSE(is_valid_token("short"));
  EXPECT_FALSE(is_valid_token("has space in it 0123"));
  EXPECT_FALSE(is_valid_token("comma,is,not,allowed,0123"));
}

TEST(RequestAuth, NoTokenIsAViewer) {
  EXPECT_EQ(authenticate(upgrade(), kToken), AuthOutcome::kViewer);
  EXPECT_EQ(authenticate(upgrade("strata.v1"), kToken), AuthOutcome::kViewer);
}

TEST(RequestAuth, BearerHeader) {
  auto request = upgrade();
  request.set(http::field::authorization, "Bearer " + std::string(kToken));
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kOperator);
  request.set(http::field::authorization, "bearer " + std::string(kToken));  // the scheme is case-insensitive
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kOperator);
  request.set(http::field::authorization, "Bearer nope");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kBadToken);
  // Another scheme is refused too, and says which to use.
  request.set(http::field::authorization, "Basic dXNlcjpwYXNz");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kWrongScheme);
  request.set(http::field::authorization, "Token " + std::string(kToken));
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kWrongScheme);
  EXPECT_NE(refusal_reason(AuthOutcome::kWrongScheme).find("Authorization: Bearer <token>"),
            std::string_view::npos);
  EXPECT_EQ(refusal_reason(AuthOutcome::kBadToken), "the operator token is wrong");
}

TEST(RequestAuth, SubprotocolCarriesTheTokenForBrowsers) {
  EXPECT_EQ(authenticate(upgrade("strata.v1, strata.token." + std::string(kToken)), kToken),
            AuthOutcome::kOperator);
  EXPECT_EQ(authenticate(upgrade("strata.v1, strata.token.guess"), kToken), AuthOutcome::kBadToken);
}

TEST(RequestAuth, CookieOnlyFromTheSameOrigin) {
  auto request = upgrade();
  request.set(http::field::cookie, "a=b; strata_token=" + std::string(kToken));
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kViewer);  // no Origin: not trusted
  request.set(http::field::origin, "https://attacker.example");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kViewer);
  request.set(http::field::origin, "null");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kViewer);
  request.set(http::field::origin, "http://robot:8080");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kOperator);
  request.set(http::field::cookie, "strata_token=stale");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kViewer);  // a stale cookie still lets the page watch
}

TEST(RequestAuth, WithoutAConfiguredTokenNobodyOperates) {
  auto request = upgrade();
  request.set(http::field::authorization, "Bearer ");
  EXPECT_EQ(authenticate(request, ""), AuthOutcome::kBadToken);
  EXPECT_EQ(authenticate(upgrade(), ""), AuthOutcome::kViewer);
}

TEST(OriginPolicy, NoOriginTheServerItselfAndListedOriginsMayUpgrade) {
  const std::vector<std::string> none;
  const std::vector<std::string> kiosk{"https://kiosk.example:8443/"};
  auto request = upgrade();
  EXPECT_TRUE(origin_allowed(request, none));  // a script: no Origin header
  request.set(http::field::origin, "http://robot:8080");
  EXPECT_TRUE(origin_allowed(request, none));  // the web app the server serves
  request.set(http::field::origin, "https://kiosk.example:8443");
  EXPECT_FALSE(origin_allowed(request, none));
  EXPECT_TRUE(origin_allowed(request, kiosk));  // listed (a trailing '/' in the list does not matter)
  EXPECT_TRUE(origin_allowed(request, {"*"}));
  request.set(http::field::origin, "https://kiosk.example:8444");
  EXPECT_FALSE(origin_allowed(request, kiosk));
  request.set(http::field::origin, "http://robot:8081");  // the same host on another port is another origin
  EXPECT_FALSE(origin_allowed(request, none));
  request.set(http::field::origin, "null");
  EXPECT_FALSE(origin_allowed(request, kiosk));
  EXPECT_TRUE(origin_allowed(request, {"null"}));
}

TEST(OriginPolicy, OnlyOriginsAreValidPatterns) {
  for (const char* good : {"*", "null", "http://kiosk", "https://kiosk.example:8443", "http://10.0.0.5:3000/",
                           "http://[::1]:8080"})
    EXPECT_TRUE(is_valid_origin_pattern(good)) << good;
  for (const char* bad : {"", "kiosk.example", "ftp://kiosk", "https://", "https://kiosk/app", "http://a b",
                          "https://kiosk.example, https://other"})
    EXPECT_FALSE(is_valid_origin_pattern(bad)) << bad;
}

}  // namespace
}  // namespace strata::auth

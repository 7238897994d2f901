#include <gtest/gtest.h>

#include <set>

#include "server/auth/operator_token.hpp"
#include "server/auth/request_auth.hpp"

namespace strata::auth {
namespace {

namespace http = net::http;
constexpr std::string_view kToken = "Sesame-0123456789_abc";

net::HttpRequest upgrade(std::string protocols = {}) {
  net::HttpRequest request{http::verb::get, "/ws", 11};
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
  request.set(http::field::authorization, "Basic dXNlcjpwYXNz");
  EXPECT_EQ(authenticate(request, kToken), AuthOutcome::kBadToken);
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

}  // namespace
}  // namespace strata::auth

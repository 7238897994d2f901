#include <gtest/gtest.h>

#include "server/net/websocket_session.hpp"

namespace strata::net {
namespace {

TEST(Subprotocol, AcceptsOursOrNone) {
  EXPECT_TRUE(accepts_subprotocol(""));
  EXPECT_TRUE(accepts_subprotocol("strata.v1"));
  EXPECT_TRUE(accepts_subprotocol("other, strata.v1"));
  EXPECT_TRUE(accepts_subprotocol(" strata.v1 ,x"));
}

TEST(Subprotocol, RefusesOthers) {
  EXPECT_FALSE(accepts_subprotocol("strata.v2"));
  EXPECT_FALSE(accepts_subprotocol("chat, superchat"));
  EXPECT_FALSE(accepts_subprotocol("strata.v1x"));
}

}  // namespace
}  // namespace strata::net

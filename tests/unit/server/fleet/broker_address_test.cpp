#include "server/fleet/broker_address.hpp"

#include <gtest/gtest.h>

#include <string>

namespace strata::fleet {
namespace {

TEST(BrokerAddress, ReadsHostPortAndScheme) {
  const auto plain = parse_broker_url("mqtt://127.0.0.1:18830");
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->host, "127.0.0.1");
  EXPECT_EQ(plain->port, 18830);
  EXPECT_FALSE(plain->tls);
  const auto secure = parse_broker_url("mqtts://broker.example.org");
  ASSERT_TRUE(secure);
  EXPECT_TRUE(secure->tls);
  EXPECT_EQ(secure->port, 8883);
  const auto v6 = parse_broker_url("mqtt://[::1]:1884");
  ASSERT_TRUE(v6);
  EXPECT_EQ(v6->host, "::1");
  EXPECT_EQ(v6->port, 1884);
}

TEST(BrokerAddress, RefusesWhatIsNoBroker) {
  std::string error;
  for (const char* wrong : {"http://host:1883", "mqtt://", "mqtt://host:0", "mqtt://host:70000",
                            "mqtt://host:12x", "mqtt://user@host", "mqtt://host/path", "mqtt://[::1"}) {
    EXPECT_FALSE(parse_broker_url(wrong, &error)) << wrong;
    EXPECT_FALSE(error.empty()) << wrong;
  }
}

}  // namespace
}  // namespace strata::fleet

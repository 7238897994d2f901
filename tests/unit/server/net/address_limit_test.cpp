#include "server/net/address_limit.hpp"

#include <gtest/gtest.h>

#include <boost/asio/ip/address.hpp>
#include <optional>
#include <vector>

namespace strata::net {
namespace {

using boost::asio::ip::make_address;

TEST(AddressLimit, EachAddressHasItsOwnPlaces) {
  AddressLimit limit(2);
  std::vector<AddressLimit::Slot> crowd;
  for (int i = 0; i < 2; ++i)
    crowd.push_back(*limit.try_acquire(make_address("10.0.0.7")));
  EXPECT_FALSE(limit.try_acquire(make_address("10.0.0.7")));
  // Another host is not affected by the first one's crowd.
  EXPECT_TRUE(limit.try_acquire(make_address("10.0.0.8")));
  EXPECT_TRUE(limit.try_acquire(make_address("fe80::1")));
  EXPECT_EQ(limit.addresses(), 1u);  // the others were given back at once
  crowd.pop_back();
  EXPECT_TRUE(limit.try_acquire(make_address("10.0.0.7")));
}

TEST(AddressLimit, AnIpv4AddressAndItsMappedFormAreOneHost) {
  AddressLimit limit(1);
  const auto slot = limit.try_acquire(make_address("192.168.1.20"));
  ASSERT_TRUE(slot);
  EXPECT_FALSE(limit.try_acquire(make_address("::ffff:192.168.1.20")));
}

TEST(AddressLimit, AMovedSlotGivesItsPlaceBackOnce) {
  AddressLimit limit(1);
  std::optional<AddressLimit::Slot> first = limit.try_acquire(make_address("10.0.0.7"));
  {
    const AddressLimit::Slot moved = std::move(*first);
    first.reset();  // moved from: gives nothing back
    EXPECT_FALSE(limit.try_acquire(make_address("10.0.0.7")));
  }
  EXPECT_EQ(limit.addresses(), 0u);
  EXPECT_TRUE(limit.try_acquire(make_address("10.0.0.7")));
}

}  // namespace
}  // namespace strata::net

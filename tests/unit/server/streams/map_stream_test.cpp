#include "server/streams/map_stream.hpp"

#include <gtest/gtest.h>

#include "server/protocol/binary_frames.hpp"

namespace strata::streams {
namespace {

std::shared_ptr<const EncodedTile> tile(int x, int y, std::uint64_t version) {
  return std::make_shared<const EncodedTile>(
      EncodedTile{x, y, version, 1, {static_cast<std::uint8_t>(version)}});
}

std::optional<EncodedTile> decode(const streams::OutgoingMessage& message) {
  const std::string& frame = *message.payload;
  return protocol::decode_tile_frame({reinterpret_cast<const std::uint8_t*>(frame.data()), frame.size()});
}

TEST(MapStream, SendsOnlyWhatChangedAndEverythingToLateJoiners) {
  MapState state;
  MapStream stream(state);
  EXPECT_TRUE(stream.poll().empty());  // no map yet

  auto a = tile(0, 0, 1);
  auto b = tile(1, 0, 1);
  auto first = std::make_shared<MapSnapshot>();
  first->version = 1;
  first->tiles = {a, b};
  state.publish(first);
  auto sent = stream.poll();
  ASSERT_EQ(sent.size(), 2u);
  EXPECT_TRUE(sent[0].binary);
  EXPECT_TRUE(stream.poll().empty());  // same snapshot: nothing new

  auto b2 = tile(1, 0, 2);
  auto second = std::make_shared<MapSnapshot>();
  second->version = 2;
  second->tiles = {a, b2};  // a unchanged (same pointer)
  state.publish(second);
  sent = stream.poll();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(decode(sent[0])->version, 2u);
  EXPECT_EQ(sent[0].coalesce_key, MapStream::tile_key(1, 0));

  const auto late = stream.current();
  EXPECT_EQ(late.size(), 2u);
}

TEST(MapStream, ATileThatIsGoneIsSentEmptyAndOrdersKeepRising) {
  MapState state;
  MapStream stream(state);
  auto first = std::make_shared<MapSnapshot>();
  first->version = 50;
  first->tiles = {tile(0, 0, 50), tile(5, 5, 40)};
  state.publish(first);
  const auto initial = stream.poll();
  double highest = 0.0;
  for (const auto& message : initial) {
    ASSERT_TRUE(message.order);  // map frames are ordered
    highest = std::max(highest, *message.order);
  }

  // A loaded map with a lower version: clients must still take its tiles, so orders are not versions.
  auto loaded = std::make_shared<MapSnapshot>();
  loaded->version = 3;
  loaded->tiles = {tile(0, 0, 3)};
  state.publish(loaded);
  const auto sent = stream.poll();
  ASSERT_EQ(sent.size(), 2u);
  for (const auto& message : sent) {
    ASSERT_TRUE(message.order);
    EXPECT_GT(*message.order, highest);
    const auto frame = decode(message);
    ASSERT_TRUE(frame);
    if (frame->tile_x == 5)
      EXPECT_TRUE(frame->draco.empty());  // gone
    else
      EXPECT_EQ(frame->version, 3u);
  }
  EXPECT_EQ(stream.current().size(), 1u);
}

}  // namespace
}  // namespace strata::streams

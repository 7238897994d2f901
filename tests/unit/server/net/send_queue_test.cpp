#include "server/net/send_queue.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace strata::net {
namespace {

std::string body(const streams::OutgoingMessage* message) {
  return message ? *message->payload : "<none>";
}

TEST(SendQueue, WritesInOrderOneAtATime) {
  SendQueue queue(8);
  queue.push(streams::OutgoingMessage::text("a"));
  queue.push(streams::OutgoingMessage::text("b"));
  EXPECT_EQ(body(queue.start_write()), "a");
  EXPECT_EQ(queue.start_write(), nullptr);  // one write in flight
  queue.finish_write();
  EXPECT_EQ(body(queue.start_write()), "b");
  queue.finish_write();
  EXPECT_EQ(queue.start_write(), nullptr);
  EXPECT_EQ(queue.size(), 0u);
}

TEST(SendQueue, NewestPoseReplacesAnUnsentOne) {
  SendQueue queue(8);
  queue.push(streams::OutgoingMessage::text("hello"));
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose1", "pose")), SendQueue::PushResult::kQueued);
  queue.push(streams::OutgoingMessage::text("status"));
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose2", "pose")), SendQueue::PushResult::kCoalesced);
  EXPECT_EQ(queue.size(), 3u);
  std::vector<std::string> sent;
  while (const streams::OutgoingMessage* next = queue.start_write()) {
    sent.push_back(*next->payload);
    queue.finish_write();
  }
  EXPECT_EQ(sent, (std::vector<std::string>{"hello", "pose2", "status"}));
}

TEST(SendQueue, NeverReplacesTheMessageBeingWritten) {
  SendQueue queue(8);
  queue.push(streams::OutgoingMessage::text("pose1", "pose"));
  const streams::OutgoingMessage* writing = queue.start_write();
  ASSERT_NE(writing, nullptr);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose2", "pose")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(*writing->payload, "pose1");  // the buffer in flight is untouched
  queue.finish_write();
  EXPECT_EQ(body(queue.start_write()), "pose2");
}

TEST(SendQueue, OverflowsWhenFullOfMessagesThatCannotBeDropped) {
  SendQueue queue(2);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("a")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("p", "pose")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("b")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("c")), SendQueue::PushResult::kOverflow);
  // A coalescing message still fits: it replaces its older self.
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("p2", "pose")), SendQueue::PushResult::kCoalesced);
  EXPECT_EQ(queue.size(), 3u);
}

TEST(SendQueue, CoalescingMessagesAreBoundedByTheirKeysNotTheCapacity) {
  SendQueue queue(4);
  // A late joiner's map: many tiles, more than the capacity, each under its own key.
  for (int round = 1; round <= 3; ++round) {
    for (int tile = 0; tile < 100; ++tile) {
      const auto result = queue.push(streams::OutgoingMessage::text(
          "t" + std::to_string(tile) + "v" + std::to_string(round), "tile:" + std::to_string(tile), round));
      EXPECT_NE(result, SendQueue::PushResult::kOverflow);
    }
  }
  EXPECT_EQ(queue.size(), 100u);  // newer versions replaced the queued older ones
  EXPECT_EQ(body(queue.start_write()), "t0v3");
  queue.finish_write();
  // Tile 0 was written; its next version queues at the back, tile 1's replaces in place.
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("t0v4", "tile:0", 4)), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("t1v4", "tile:1", 4)),
            SendQueue::PushResult::kCoalesced);
  EXPECT_EQ(body(queue.start_write()), "t1v4");
  queue.finish_write();
  std::string last;
  while (const streams::OutgoingMessage* next = queue.start_write()) {
    last = *next->payload;
    queue.finish_write();
  }
  EXPECT_EQ(last, "t0v4");
}

TEST(SendQueue, AnOlderTileVersionIsDropped) {
  SendQueue queue(4);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("v5", "tile:3,4", 5)), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("v4", "tile:3,4", 4)), SendQueue::PushResult::kStale);
  EXPECT_EQ(body(queue.start_write()), "v5");
}

TEST(SendQueue, AStreamNeverGoesBackwardsOrRepeats) {
  SendQueue queue(8);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@2", "pose", 2.0)),
            SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@2 again", "pose", 2.0)),
            SendQueue::PushResult::kStale);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@1", "pose", 1.0)), SendQueue::PushResult::kStale);
  ASSERT_NE(queue.start_write(), nullptr);
  queue.finish_write();
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@1.5", "pose", 1.5)),
            SendQueue::PushResult::kStale);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@3", "pose", 3.0)),
            SendQueue::PushResult::kQueued);
  EXPECT_EQ(body(queue.start_write()), "pose@3");
}

TEST(SendQueue, AZeroStampIsAnOrderLikeAnyOther) {
  // The simulator's first pose is stamped 0: the late joiner's snapshot and the first broadcast both carry
  // it, and the client must see it once.
  SendQueue queue(8);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@0", "pose", 0.0)),
            SendQueue::PushResult::kQueued);
  ASSERT_NE(queue.start_write(), nullptr);
  queue.finish_write();
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("pose@0 again", "pose", 0.0)),
            SendQueue::PushResult::kStale);
  // Unordered messages (status) always supersede.
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("s1", "status")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(streams::OutgoingMessage::text("s2", "status")), SendQueue::PushResult::kCoalesced);
}

streams::OutgoingMessage tile(std::string body, int tile_id, double version) {
  return streams::OutgoingMessage::map_frame(std::move(body), "tile:" + std::to_string(tile_id), version, 0);
}

TEST(SendQueue, ThePoseGoesAheadOfTheMapButNeverCutsIntoAWrite) {
  SendQueue queue(8);
  for (int id = 0; id < 3; ++id)
    queue.push(tile("t" + std::to_string(id), id, 1));
  EXPECT_EQ(body(queue.start_write()), "t0");
  // The pose and a reply arrive while the first tile is being written: both go before the other tiles,
  // in the order they came, and the tile being written finishes first.
  queue.push(streams::OutgoingMessage::text("pose1", "pose", 1.0));
  queue.push(streams::OutgoingMessage::text("ack"));
  EXPECT_EQ(queue.start_write(), nullptr);
  queue.finish_write();
  std::vector<std::string> sent;
  while (const streams::OutgoingMessage* next = queue.start_write()) {
    sent.push_back(*next->payload);
    queue.finish_write();
    if (sent.size() == 3)
      queue.push(streams::OutgoingMessage::text("pose2", "pose", 2.0));  // between two tiles
  }
  EXPECT_EQ(sent, (std::vector<std::string>{"pose1", "ack", "t1", "pose2", "t2"}));
}

TEST(SendQueue, CountsTheBytesWaitingAndWhatALaggingClientDidNotGet) {
  SendQueue queue(8);
  queue.push(tile("12345", 0, 1));
  queue.push(streams::OutgoingMessage::text("pose-1", "pose", 1.0));
  queue.push(streams::OutgoingMessage::text("pose-22", "pose", 2.0));   // supersedes pose-1
  queue.push(streams::OutgoingMessage::text("pose-333", "pose", 3.0));  // and pose-22
  queue.push(streams::OutgoingMessage::text("ok"));
  EXPECT_EQ(queue.bytes(), 5u + 8u + 2u);
  EXPECT_EQ(queue.superseded(), 2u);
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(body(queue.start_write()), "pose-333");
  EXPECT_EQ(queue.bytes(), 15u);  // the message in flight still counts
  queue.finish_write();
  EXPECT_EQ(queue.bytes(), 7u);
  while (queue.start_write() != nullptr)
    queue.finish_write();
  EXPECT_EQ(queue.bytes(), 0u);
  EXPECT_EQ(queue.size(), 0u);
}

}  // namespace
}  // namespace strata::net

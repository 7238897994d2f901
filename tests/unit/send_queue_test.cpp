#include "server/net/send_queue.hpp"

#include <gtest/gtest.h>

namespace strata::net {
namespace {

std::string body(const OutgoingMessage* message) {
  return message ? *message->payload : "<none>";
}

TEST(SendQueue, WritesInOrderOneAtATime) {
  SendQueue queue(8);
  queue.push(OutgoingMessage::text("a"));
  queue.push(OutgoingMessage::text("b"));
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
  queue.push(OutgoingMessage::text("hello"));
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose1", "pose")), SendQueue::PushResult::kQueued);
  queue.push(OutgoingMessage::text("status"));
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose2", "pose")), SendQueue::PushResult::kCoalesced);
  EXPECT_EQ(queue.size(), 3u);
  std::vector<std::string> sent;
  while (const OutgoingMessage* next = queue.start_write()) {
    sent.push_back(*next->payload);
    queue.finish_write();
  }
  EXPECT_EQ(sent, (std::vector<std::string>{"hello", "pose2", "status"}));
}

TEST(SendQueue, NeverReplacesTheMessageBeingWritten) {
  SendQueue queue(8);
  queue.push(OutgoingMessage::text("pose1", "pose"));
  const OutgoingMessage* writing = queue.start_write();
  ASSERT_NE(writing, nullptr);
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose2", "pose")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(*writing->payload, "pose1");  // the buffer in flight is untouched
  queue.finish_write();
  EXPECT_EQ(body(queue.start_write()), "pose2");
}

TEST(SendQueue, OverflowsWhenFullOfMessagesThatCannotBeDropped) {
  SendQueue queue(2);
  EXPECT_EQ(queue.push(OutgoingMessage::text("a")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(OutgoingMessage::text("p", "pose")), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(OutgoingMessage::text("b")), SendQueue::PushResult::kOverflow);
  // A coalescing message still fits: it replaces its older self.
  EXPECT_EQ(queue.push(OutgoingMessage::text("p2", "pose")), SendQueue::PushResult::kCoalesced);
  EXPECT_EQ(queue.size(), 2u);
}

TEST(SendQueue, AStreamNeverGoesBackwardsOrRepeats) {
  SendQueue queue(8);
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose@2", "pose", 2.0)), SendQueue::PushResult::kQueued);
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose@2 again", "pose", 2.0)), SendQueue::PushResult::kStale);
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose@1", "pose", 1.0)), SendQueue::PushResult::kStale);
  ASSERT_NE(queue.start_write(), nullptr);
  queue.finish_write();
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose@1.5", "pose", 1.5)), SendQueue::PushResult::kStale);
  EXPECT_EQ(queue.push(OutgoingMessage::text("pose@3", "pose", 3.0)), SendQueue::PushResult::kQueued);
  EXPECT_EQ(body(queue.start_write()), "pose@3");
}

}  // namespace
}  // namespace strata::net

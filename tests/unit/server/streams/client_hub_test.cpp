#include "server/streams/client_hub.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace strata::streams {
namespace {

// A client that records what it is sent (the hub's contract is only "send must not block").
class RecordingClient : public ClientConnection {
 public:
  explicit RecordingClient(std::uint64_t id = 0) : id_(id) {}
  void send(OutgoingMessage message) override { received.push_back(*message.payload); }
  [[nodiscard]] ClientStats stats() const override { return {.id = id_, .queued_bytes = received.size()}; }
  std::vector<std::string> received;

 private:
  std::uint64_t id_;
};

TEST(ClientHub, BroadcastReachesEveryJoinedClient) {
  ClientHub hub;
  auto a = std::make_shared<RecordingClient>();
  auto b = std::make_shared<RecordingClient>();
  hub.join(a);
  hub.join(b);
  hub.broadcast(OutgoingMessage::text("x"));
  EXPECT_EQ(a->received, std::vector<std::string>{"x"});
  EXPECT_EQ(b->received, std::vector<std::string>{"x"});
  EXPECT_EQ(hub.size(), 2u);
}

TEST(ClientHub, LeftClientsGetNothing) {
  ClientHub hub;
  auto a = std::make_shared<RecordingClient>();
  hub.join(a);
  hub.leave(a.get());
  hub.broadcast(OutgoingMessage::text("x"));
  EXPECT_TRUE(a->received.empty());
  EXPECT_EQ(hub.size(), 0u);
}

TEST(ClientHub, ExpiredClientsAreSkipped) {
  ClientHub hub;
  auto a = std::make_shared<RecordingClient>();
  auto b = std::make_shared<RecordingClient>();
  hub.join(a);
  hub.join(b);
  a.reset();  // destroyed without leaving: broadcasting must not touch it (ASan would see it)
  hub.broadcast(OutgoingMessage::text("x"));
  EXPECT_EQ(b->received, std::vector<std::string>{"x"});  // the others still get it
  EXPECT_EQ(hub.stats().size(), 1u);                      // and only they are listed
}

TEST(ClientHub, StatsListEveryLiveClientInTheOrderTheyCame) {
  ClientHub hub;
  auto third = std::make_shared<RecordingClient>(3);
  auto first = std::make_shared<RecordingClient>(1);
  auto gone = std::make_shared<RecordingClient>(2);
  hub.join(third);
  hub.join(first);
  hub.join(gone);
  gone.reset();
  hub.broadcast(OutgoingMessage::text("x"));
  const auto stats = hub.stats();
  ASSERT_EQ(stats.size(), 2u);
  EXPECT_EQ(stats[0].id, 1u);
  EXPECT_EQ(stats[1].id, 3u);
  EXPECT_EQ(stats[1].queued_bytes, 1u);
}

TEST(ClientHub, PayloadIsSharedNotCopied) {
  ClientHub hub;
  std::vector<const std::string*> seen;
  class PointerClient : public ClientConnection {
   public:
    explicit PointerClient(std::vector<const std::string*>& out) : out_(out) {}
    void send(OutgoingMessage message) override { out_.push_back(message.payload.get()); }
    [[nodiscard]] ClientStats stats() const override { return {}; }

   private:
    std::vector<const std::string*>& out_;
  };
  auto a = std::make_shared<PointerClient>(seen);
  auto b = std::make_shared<PointerClient>(seen);
  hub.join(a);
  hub.join(b);
  hub.broadcast(OutgoingMessage::text("payload"));
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0], seen[1]);
}

}  // namespace
}  // namespace strata::streams

#pragma once

#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <memory>
#include <string_view>

#include "server/auth/operator_token.hpp"
#include "server/control/teleop_freshness.hpp"
#include "server/net/address_limit.hpp"
#include "server/net/connection_limit.hpp"
#include "server/net/rate_limiter.hpp"
#include "server/net/send_queue.hpp"
#include "server/net/server_context.hpp"
#include "server/net/transport.hpp"
#include "server/protocol/client_messages.hpp"
#include "server/protocol/http_types.hpp"
#include "server/streams/client_hub.hpp"

namespace strata::net {

/// One WebSocket client on /ws. Everything runs on the session's strand (the executor of its socket);
/// outgoing messages wait in a bounded, coalescing SendQueue with one write in flight. The client's role
/// (viewer or operator) is fixed at the upgrade; its subscriptions filter what it is sent. `Stream` is the
/// HTTP session's stream it takes over: PlainStream, or TlsStream (wss://, the handshake already done).
template <class Stream>
class WebSocketSession : public streams::ClientConnection,
                         public std::enable_shared_from_this<WebSocketSession<Stream>> {
 public:
  /// `slot`, `address_slot`: this client's places under the WebSocket client limit and its address's,
  /// held until the session ends.
  WebSocketSession(Stream&& stream, std::shared_ptr<ServerContext> context, auth::Role role,
                   ConnectionLimit::Slot slot, AddressLimit::Slot address_slot);
  ~WebSocketSession() override;

  /// Completes the upgrade `request` asked for, then starts streaming.
  void run(protocol::HttpRequest request);
  void send(streams::OutgoingMessage message) override;
  [[nodiscard]] streams::ClientStats stats() const override;

 private:
  void bound_what_the_socket_holds();
  void on_accept(boost::beast::error_code error);
  void read_next();
  void on_read(boost::beast::error_code error, std::size_t bytes);
  void handle_client_message(std::string_view text);
  void handle_request(const protocol::ClientRequest& request, std::string_view op, const nlohmann::json& id);
  /// A save or load: runs on ServerContext::map_work, off the network threads; the reply comes after.
  void run_off_the_network(const protocol::ClientRequest& request, std::string_view op,
                           const nlohmann::json& id);
  void reply(const CommandResult& result, std::string_view op, const nlohmann::json& id);
  void enqueue(streams::OutgoingMessage message);
  void drop_client(std::string_view why);
  void write_next();
  void on_write(boost::beast::error_code error, std::size_t bytes);
  void publish_stats(const streams::OutgoingMessage* written);

  boost::beast::websocket::stream<Stream> ws_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<ServerContext> context_;
  ConnectionLimit::Slot slot_;  // after context_: given back before the context can go
  AddressLimit::Slot address_slot_;
  auth::Role role_;
  SendQueue queue_;
  RateLimiter limiter_;
  protocol::StreamSet streams_ = protocol::kAllStreams;
  std::chrono::steady_clock::time_point write_started_{};
  bool open_ = false;
  bool teleoperating_ = false;
  TeleopFreshness teleop_freshness_;  // refuses moving teleops that are stale or out of order
  std::uint64_t goal_id_ = 0;         // the last goal this connection set: cancelled when it closes
  // What stats() reads from other threads; written on the strand as the queue and the writes move.
  std::uint64_t id_ = 0;
  std::atomic<std::size_t> queued_bytes_{0};
  std::atomic<std::size_t> socket_bytes_{0};
  std::atomic<std::uint64_t> superseded_{0};
  std::atomic<double> pose_age_s_{-1.0};  // negative: no pose written yet
};

extern template class WebSocketSession<PlainStream>;
extern template class WebSocketSession<TlsStream>;

/// Whether an upgrade request's Sec-WebSocket-Protocol list is acceptable: absent, or naming ours.
[[nodiscard]] bool accepts_subprotocol(std::string_view offered);

}  // namespace strata::net

#include "server/net/websocket_session.hpp"

#include <linux/sockios.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <spdlog/spdlog.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <variant>

#include "drivers/io/text_fields.hpp"
#include "server/api/operator_commands.hpp"
#include "server/auth/log_throttle.hpp"
#include "server/control/server_clock.hpp"
#include "server/protocol/messages.hpp"
#include "server/protocol/protocol.hpp"

namespace strata::net {
namespace {

using io::trimmed;  // header values: blanks around list items and values do not count

namespace beast = boost::beast;
namespace websocket = beast::websocket;
using protocol::ErrorCode;

// Replies and errors a client may leave unread before it counts as stuck; streams coalesce and never pile up.
constexpr std::size_t kSendQueueCapacity = 256;
// Client messages: teleop at 20 Hz plus clicks fits easily; a flood gets rate_limited errors.
constexpr double kMessagesPerSecond = 40.0;
constexpr double kMessageBurst = 80.0;
// A write that has not completed in this long means the client stopped reading: drop it, so its socket
// buffers and queue are freed and nobody waits for it.
constexpr auto kStalledWriteTimeout = std::chrono::seconds(10);

// Unsent bytes the kernel may hold for a client (TCP_NOTSENT_LOWAT). Whatever waits beyond it waits in the
// session's queue, where a newer pose replaces an older one and the pose goes ahead of map tiles; bytes
// handed to the kernel can only be sent in order, however stale. 4 KiB is 0.16 s of the slowest link we
// serve (0.2 Mbit/s), so a pose waits behind that and one tile at most. The bytes on the wire are TCP's to
// bound (its window), not ours.
constexpr int kSocketUnsentBytes = 4 * 1024;

// Clients are numbered in /metrics and the log by the order they came.
std::atomic<std::uint64_t> next_client_id{1};

// What clients coming, going and misbehaving put into the log (LogThrottle): a client reconnecting in a
// loop would otherwise write two lines a connection.
auth::LogThrottle clients_log(2.0, 20.0);
auth::LogThrottle misbehaving_log;

}  // namespace

bool accepts_subprotocol(std::string_view offered) {
  if (trimmed(offered).empty())
    return true;  // plain clients (scripts, wscat) get v1
  while (!offered.empty()) {
    const std::size_t comma = offered.find(',');
    if (trimmed(offered.substr(0, comma)) == protocol::kSubprotocol)
      return true;
    if (comma == std::string_view::npos)
      break;
    offered.remove_prefix(comma + 1);
  }
  return false;
}

template <class Stream>
WebSocketSession<Stream>::WebSocketSession(Stream&& stream, std::shared_ptr<ServerContext> context,
                                           auth::Role role, ConnectionLimit::Slot slot,
                                           AddressLimit::Slot address_slot)
    : ws_(std::move(stream)),
      context_(std::move(context)),
      slot_(std::move(slot)),
      address_slot_(std::move(address_slot)),
      role_(role),
      queue_(kSendQueueCapacity),
      limiter_(kMessagesPerSecond, kMessageBurst),
      id_(next_client_id.fetch_add(1, std::memory_order_relaxed)) {}

template <class Stream>
WebSocketSession<Stream>::~WebSocketSession() {
  // A dropped connection stops the robot it was driving by hand (docs/architecture.md 6), and cancels the
  // goal it set if that goal is still the one being driven: an operator who is gone cannot watch or stop the
  // robot any more. (A goal set over REST has no connection and runs on.)
  if (teleoperating_ && context_->services.motion != nullptr)
    context_->services.motion->stop_teleop();
  if (goal_id_ != 0 && context_->services.motion != nullptr &&
      context_->services.motion->cancel_goal_if_active(goal_id_, "operator_disconnected")) {
    spdlog::warn("the operator connection that set goal {} closed: goal cancelled, the robot stops",
                 goal_id_);
  }
  // Last: once the status no longer counts this client, its goal is already cancelled.
  context_->hub.leave(this);
  if (open_) {
    if (const auto held = clients_log.admit())
      spdlog::info("websocket client left ({} connected){}", context_->hub.size(), auth::held_back(*held));
  }
}

template <class Stream>
void WebSocketSession<Stream>::bound_what_the_socket_holds() {
  auto& socket = beast::get_lowest_layer(ws_).socket();
  beast::error_code ignored;
  // Small messages (a pose) leave at once instead of waiting for the next segment to fill.
  socket.set_option(boost::asio::ip::tcp::no_delay(true), ignored);
  socket.set_option(
      boost::asio::detail::socket_option::integer<IPPROTO_TCP, TCP_NOTSENT_LOWAT>(kSocketUnsentBytes),
      ignored);
}

template <class Stream>
void WebSocketSession<Stream>::run(protocol::HttpRequest request) {
  bound_what_the_socket_holds();
  auto timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
  // Pings at half the idle time: a client that stops answering (gone, or not reading) is dropped.
  timeouts.idle_timeout = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(context_->services.network.client_timeout_s));
  timeouts.keep_alive_pings = true;
  ws_.set_option(timeouts);
  ws_.read_message_max(protocol::kMaxClientMessageBytes);
  const bool echo_subprotocol = !trimmed(request[http::field::sec_websocket_protocol]).empty();
  ws_.set_option(websocket::stream_base::decorator([echo_subprotocol](websocket::response_type& response) {
    response.set(http::field::server, "strata");
    if (echo_subprotocol)
      response.set(http::field::sec_websocket_protocol, protocol::kSubprotocol);
  }));
  ws_.async_accept(request,
                   beast::bind_front_handler(&WebSocketSession::on_accept, this->shared_from_this()));
}

template <class Stream>
void WebSocketSession<Stream>::on_accept(beast::error_code error) {
  if (error) {
    if (const auto held = misbehaving_log.admit())
      spdlog::warn("websocket handshake failed: {}{}", error.message(), auth::held_back(*held));
    return;
  }
  open_ = true;
  context_->metrics.ws_connections.fetch_add(1, std::memory_order_relaxed);
  // Join the live streams first, then queue the current state, all in this one handler on the strand:
  // broadcasts reach us as posted handlers, so they queue after the state, and a frame that is in both
  // is dropped as stale by the queue (same order). Nothing is missed between snapshot and joining.
  context_->hub.join(this->shared_from_this());
  enqueue(streams::OutgoingMessage::text(
      protocol::hello_message(role_ == auth::Role::kOperator ? "operator" : "viewer", server_clock_ms())));
  if (!context_->sim_world_message.empty())
    enqueue(streams::OutgoingMessage::text(context_->sim_world_message));
  nlohmann::json status = context_->status.fields();
  status["op"] = "status";
  enqueue(streams::OutgoingMessage::text(status.dump(), "status", std::nullopt,
                                         static_cast<std::uint8_t>(protocol::Stream::kStatus)));
  if (const auto robot = context_->services.robot->snapshot()) {
    enqueue(streams::OutgoingMessage::text(protocol::pose_message(*robot), "pose",
                                           static_cast<double>(robot->version),
                                           static_cast<std::uint8_t>(protocol::Stream::kPose)));
  }
  for (auto& message : context_->current_state())
    enqueue(std::move(message));
  if (const auto held = clients_log.admit()) {
    spdlog::info("websocket client joined as {} ({} connected){}",
                 role_ == auth::Role::kOperator ? "operator" : "viewer", context_->hub.size(),
                 auth::held_back(*held));
  }
  read_next();
}

template <class Stream>
void WebSocketSession<Stream>::read_next() {
  ws_.async_read(buffer_, beast::bind_front_handler(&WebSocketSession::on_read, this->shared_from_this()));
}

template <class Stream>
void WebSocketSession<Stream>::on_read(beast::error_code error, std::size_t /*bytes*/) {
  if (error) {
    if (error == websocket::error::message_too_big) {
      if (const auto held = misbehaving_log.admit())
        spdlog::warn("websocket client sent a message over {} bytes; closing{}",
                     protocol::kMaxClientMessageBytes, auth::held_back(*held));
    } else if (error == beast::error::timeout && open_) {
      // Neither a message nor an answer to the ping: gone, or not reading what it is sent.
      context_->metrics.ws_slow_dropped.fetch_add(1, std::memory_order_relaxed);
      if (const auto held = misbehaving_log.admit())
        spdlog::warn("websocket client {} silent for {} s (no answer to the ping); disconnecting{}", id_,
                     context_->services.network.client_timeout_s, auth::held_back(*held));
    }
    return;  // closed or failed: the session ends when its last handler completes
  }
  context_->metrics.ws_messages_in.fetch_add(1, std::memory_order_relaxed);
  if (!limiter_.allow(std::chrono::steady_clock::now())) {
    context_->metrics.ws_rate_limited.fetch_add(1, std::memory_order_relaxed);
    context_->metrics.ws_errors_sent.fetch_add(1, std::memory_order_relaxed);
    enqueue(streams::OutgoingMessage::text(protocol::error_message(
        ErrorCode::kRateLimited, "too many messages: at most " +
                                     std::to_string(static_cast<int>(kMessagesPerSecond)) +
                                     " per second on average")));
  } else if (ws_.got_binary()) {
    context_->metrics.ws_errors_sent.fetch_add(1, std::memory_order_relaxed);
    enqueue(streams::OutgoingMessage::text(
        protocol::error_message(ErrorCode::kBadMessage, "binary frames from clients are not accepted")));
  } else {
    handle_client_message(beast::buffers_to_string(buffer_.data()));
  }
  buffer_.consume(buffer_.size());
  read_next();
}

template <class Stream>
void WebSocketSession<Stream>::handle_client_message(std::string_view text) {
  const auto parsed = protocol::parse_client_message(text);
  if (!parsed.request) {
    context_->metrics.ws_errors_sent.fetch_add(1, std::memory_order_relaxed);
    enqueue(streams::OutgoingMessage::text(
        protocol::error_message(parsed.error, parsed.error_message, parsed.op, parsed.id)));
    return;
  }
  if (protocol::needs_operator(*parsed.request) && role_ != auth::Role::kOperator) {
    context_->metrics.ws_errors_sent.fetch_add(1, std::memory_order_relaxed);
    enqueue(streams::OutgoingMessage::text(protocol::error_message(
        ErrorCode::kUnauthorized, parsed.op + " needs the operator token; this connection may only watch",
        parsed.op, parsed.id)));
    return;
  }
  handle_request(*parsed.request, parsed.op, parsed.id);
}

template <class Stream>
void WebSocketSession<Stream>::handle_request(const protocol::ClientRequest& request, std::string_view op,
                                              const nlohmann::json& id) {
  if (std::holds_alternative<protocol::PingRequest>(request)) {
    enqueue(streams::OutgoingMessage::text(protocol::pong_message(id, server_clock_ms())));
    return;
  }
  if (const auto* subscribe = std::get_if<protocol::SubscribeRequest>(&request)) {
    const protocol::StreamSet added = subscribe->streams & static_cast<protocol::StreamSet>(~streams_);
    streams_ = subscribe->streams;
    // Newly subscribed streams start with their current state, as for a late joiner.
    for (auto& message : context_->current_state()) {
      if ((message.stream & added) != 0)
        enqueue(std::move(message));
    }
    reply(CommandResult::success(), op, id);
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  const auto* teleop = std::get_if<protocol::TeleopRequest>(&request);
  if (teleop != nullptr) {
    const CommandResult fresh = teleop_freshness_.admit(teleop->stamp, teleop->moves(), server_clock_ms(now));
    if (!fresh.ok) {
      if (fresh.code == ErrorCode::kStaleCommand)
        context_->metrics.ws_stale_teleop.fetch_add(1, std::memory_order_relaxed);
      return reply(fresh, op, id);
    }
  }
  if (std::holds_alternative<protocol::SaveMapRequest>(request) ||
      std::holds_alternative<protocol::LoadMapRequest>(request)) {
    return run_off_the_network(request, op, id);
  }
  const CommandResult result = api::run_operator_command(context_->services, request, now);
  if (teleop != nullptr) {
    teleoperating_ = teleoperating_ || result.ok;
    // Teleop runs at 10-20 Hz: acknowledge only when the client asked for it (gave an id).
    if (!result.ok || !id.is_null())
      reply(result, op, id);
    return;
  }
  if (result.ok && std::holds_alternative<protocol::SetGoalRequest>(request))
    goal_id_ = result.goal_id;
  reply(result, op, id);
}

template <class Stream>
void WebSocketSession<Stream>::run_off_the_network(const protocol::ClientRequest& request,
                                                   std::string_view op, const nlohmann::json& id) {
  auto place = context_->map_work_places.try_acquire();
  if (!place) {
    return reply(CommandResult::failure(ErrorCode::kUnavailable, ServerContext::map_work_busy()), op, id);
  }
  boost::asio::post(context_->map_work, [self = this->shared_from_this(), request, op = std::string(op), id,
                                         place = std::move(*place)]() mutable {
    const CommandResult result =
        api::run_operator_command(self->context_->services, request, std::chrono::steady_clock::now());
    boost::asio::post(self->ws_.get_executor(), [self, result, op = std::move(op), id = std::move(id)] {
      self->reply(result, op, id);
    });
  });
}

template <class Stream>
void WebSocketSession<Stream>::reply(const CommandResult& result, std::string_view op,
                                     const nlohmann::json& id) {
  if (result.ok) {
    enqueue(streams::OutgoingMessage::text(protocol::ack_message(op, id, result.message)));
    return;
  }
  context_->metrics.ws_errors_sent.fetch_add(1, std::memory_order_relaxed);
  enqueue(streams::OutgoingMessage::text(protocol::error_message(result.code, result.message, op, id)));
}

template <class Stream>
void WebSocketSession<Stream>::send(streams::OutgoingMessage message) {
  boost::asio::post(ws_.get_executor(),
                    [self = this->shared_from_this(), message = std::move(message)]() mutable {
                      self->enqueue(std::move(message));
                    });
}

template <class Stream>
void WebSocketSession<Stream>::enqueue(streams::OutgoingMessage message) {
  if (!open_)
    return;
  if (message.stream != 0 && (message.stream & streams_) == 0)
    return;  // not subscribed
  if (queue_.writing() && std::chrono::steady_clock::now() - write_started_ > kStalledWriteTimeout)
    return drop_client("a write has not completed in 10 s");
  if (queue_.push(std::move(message)) == SendQueue::PushResult::kOverflow)
    return drop_client(std::to_string(queue_.size()) + " messages queued");
  write_next();
  publish_stats(nullptr);
}

template <class Stream>
void WebSocketSession<Stream>::drop_client(std::string_view why) {
  if (const auto held = misbehaving_log.admit())
    spdlog::warn("websocket client is not keeping up ({}); disconnecting{}", why, auth::held_back(*held));
  context_->metrics.ws_slow_dropped.fetch_add(1, std::memory_order_relaxed);
  open_ = false;
  context_->hub.leave(this);
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().close(ignored);
}

template <class Stream>
void WebSocketSession<Stream>::write_next() {
  const streams::OutgoingMessage* next = queue_.start_write();
  if (next == nullptr)
    return;
  write_started_ = std::chrono::steady_clock::now();
  ws_.binary(next->binary);
  ws_.async_write(boost::asio::buffer(*next->payload),
                  beast::bind_front_handler(&WebSocketSession::on_write, this->shared_from_this()));
}

template <class Stream>
void WebSocketSession<Stream>::on_write(beast::error_code error, std::size_t bytes) {
  if (error) {
    queue_.finish_write();
    open_ = false;
    return;
  }
  context_->metrics.ws_bytes_out.fetch_add(bytes, std::memory_order_relaxed);
  publish_stats(queue_.in_flight());
  queue_.finish_write();
  write_next();
}

template <class Stream>
void WebSocketSession<Stream>::publish_stats(const streams::OutgoingMessage* written) {
  queued_bytes_.store(queue_.bytes(), std::memory_order_relaxed);
  superseded_.store(queue_.superseded(), std::memory_order_relaxed);
  if (written == nullptr)
    return;
  if (written->stream == static_cast<std::uint8_t>(protocol::Stream::kPose)) {
    pose_age_s_.store(std::chrono::duration<double>(std::chrono::steady_clock::now() - written->made).count(),
                      std::memory_order_relaxed);
  }
  int unacknowledged = 0;  // SIOCOUTQ: bytes in the send buffer, sent or not, that the peer has not acked
  if (::ioctl(beast::get_lowest_layer(ws_).socket().native_handle(), SIOCOUTQ, &unacknowledged) == 0)
    socket_bytes_.store(static_cast<std::size_t>(std::max(unacknowledged, 0)), std::memory_order_relaxed);
}

template <class Stream>
streams::ClientStats WebSocketSession<Stream>::stats() const {
  const double pose_age = pose_age_s_.load(std::memory_order_relaxed);
  return {.id = id_,
          .operator_role = role_ == auth::Role::kOperator,
          .queued_bytes = queued_bytes_.load(std::memory_order_relaxed),
          .socket_bytes = socket_bytes_.load(std::memory_order_relaxed),
          .superseded = superseded_.load(std::memory_order_relaxed),
          .pose_age_s = pose_age < 0.0 ? std::nullopt : std::optional<double>(pose_age)};
}

template class WebSocketSession<PlainStream>;
template class WebSocketSession<TlsStream>;

}  // namespace strata::net

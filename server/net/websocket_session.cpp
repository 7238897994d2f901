#include "server/net/websocket_session.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "server/protocol/messages.hpp"
#include "server/protocol/protocol.hpp"

namespace strata::net {
namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
using protocol::ErrorCode;

// Enough for the late-joiner state plus a burst of control replies; poses coalesce and never pile up.
constexpr std::size_t kSendQueueCapacity = 256;

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t'))
    text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t'))
    text.remove_suffix(1);
  return text;
}

}  // namespace

bool accepts_subprotocol(std::string_view offered) {
  if (trim(offered).empty())
    return true;  // plain clients (scripts, wscat) get v1
  while (!offered.empty()) {
    const std::size_t comma = offered.find(',');
    if (trim(offered.substr(0, comma)) == protocol::kSubprotocol)
      return true;
    if (comma == std::string_view::npos)
      break;
    offered.remove_prefix(comma + 1);
  }
  return false;
}

WebSocketSession::WebSocketSession(boost::asio::ip::tcp::socket&& socket,
                                   std::shared_ptr<ServerContext> context)
    : ws_(std::move(socket)), context_(std::move(context)), queue_(kSendQueueCapacity) {}

WebSocketSession::~WebSocketSession() {
  context_->hub.leave(this);
  if (open_)
    spdlog::info("websocket client left ({} connected)", context_->hub.size());
}

void WebSocketSession::run(HttpRequest request) {
  auto timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
  // Pings at half the idle time: a client that stops answering (gone, or not reading) is dropped.
  timeouts.idle_timeout = std::chrono::seconds(20);
  timeouts.keep_alive_pings = true;
  ws_.set_option(timeouts);
  ws_.read_message_max(protocol::kMaxClientMessageBytes);
  const bool echo_subprotocol = !trim(request[http::field::sec_websocket_protocol]).empty();
  ws_.set_option(websocket::stream_base::decorator([echo_subprotocol](websocket::response_type& response) {
    response.set(http::field::server, "strata");
    if (echo_subprotocol)
      response.set(http::field::sec_websocket_protocol, protocol::kSubprotocol);
  }));
  ws_.async_accept(request, beast::bind_front_handler(&WebSocketSession::on_accept, shared_from_this()));
}

void WebSocketSession::on_accept(beast::error_code error) {
  if (error) {
    spdlog::warn("websocket handshake failed: {}", error.message());
    return;
  }
  open_ = true;
  // The late joiner's state goes first, then the client joins the live streams.
  enqueue(OutgoingMessage::text(protocol::hello_message()));
  if (!context_->sim_world_message.empty())
    enqueue(OutgoingMessage::text(context_->sim_world_message));
  enqueue(OutgoingMessage::text(
      protocol::status_message(context_->robot.registration(), context_->hub.size() + 1), "status"));
  if (const auto robot = context_->robot.snapshot()) {
    enqueue(OutgoingMessage::text(protocol::pose_message(*robot), "pose", robot->sample.stamp));
  }
  context_->hub.join(shared_from_this());
  spdlog::info("websocket client joined ({} connected)", context_->hub.size());
  read_next();
}

void WebSocketSession::read_next() {
  ws_.async_read(buffer_, beast::bind_front_handler(&WebSocketSession::on_read, shared_from_this()));
}

void WebSocketSession::on_read(beast::error_code error, std::size_t /*bytes*/) {
  if (error) {
    if (error == websocket::error::message_too_big) {
      spdlog::warn("websocket client sent a message over {} bytes; closing",
                   protocol::kMaxClientMessageBytes);
    }
    return;  // closed or failed: the session ends when its last handler completes
  }
  if (ws_.got_binary()) {
    enqueue(OutgoingMessage::text(
        protocol::error_message(ErrorCode::kBadMessage, "binary frames from clients are not accepted")));
  } else {
    handle_client_message(beast::buffers_to_string(buffer_.data()));
  }
  buffer_.consume(buffer_.size());
  read_next();
}

void WebSocketSession::handle_client_message(std::string_view text) {
  const nlohmann::json message = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) {
    enqueue(OutgoingMessage::text(protocol::error_message(ErrorCode::kBadJson, "message is not valid JSON")));
    return;
  }
  const auto op = message.is_object() ? message.find("op") : message.end();
  if (!message.is_object() || op == message.end() || !op->is_string()) {
    enqueue(OutgoingMessage::text(
        protocol::error_message(ErrorCode::kBadMessage, "a message is a JSON object with a string \"op\"")));
    return;
  }
  if (*op == "ping") {
    enqueue(OutgoingMessage::text(protocol::pong_message(message.value("id", nlohmann::json()))));
    return;
  }
  enqueue(OutgoingMessage::text(
      protocol::error_message(ErrorCode::kUnknownOp, "unknown op \"" + op->get<std::string>() + "\"")));
}

void WebSocketSession::send(OutgoingMessage message) {
  boost::asio::post(ws_.get_executor(), [self = shared_from_this(), message = std::move(message)]() mutable {
    self->enqueue(std::move(message));
  });
}

void WebSocketSession::enqueue(OutgoingMessage message) {
  if (!open_)
    return;
  if (queue_.push(std::move(message)) == SendQueue::PushResult::kOverflow) {
    spdlog::warn("websocket client is not keeping up ({} messages queued); disconnecting", queue_.size());
    open_ = false;
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
    return;
  }
  write_next();
}

void WebSocketSession::write_next() {
  const OutgoingMessage* next = queue_.start_write();
  if (next == nullptr)
    return;
  ws_.binary(next->binary);
  ws_.async_write(boost::asio::buffer(*next->payload),
                  beast::bind_front_handler(&WebSocketSession::on_write, shared_from_this()));
}

void WebSocketSession::on_write(beast::error_code error, std::size_t /*bytes*/) {
  queue_.finish_write();
  if (error) {
    open_ = false;
    return;
  }
  write_next();
}

}  // namespace strata::net

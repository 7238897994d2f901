#include "server/fleet/mqtt_link.hpp"

#include <mosquitto.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace strata::fleet {
namespace {

constexpr std::chrono::milliseconds kFirstBackoff{500};
constexpr std::chrono::milliseconds kLongestBackoff{16000};
constexpr std::chrono::seconds kTickPeriod{1};

void init_library() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

void require(int result, const char* what) {
  if (result != MOSQ_ERR_SUCCESS)
    throw std::runtime_error(std::string("MQTT: ") + what + ": " + mosquitto_strerror(result));
}

}  // namespace

MqttLink::MqttLink(Strand strand, BrokerAddress broker, const MqttSession& session, Handlers handlers)
    : strand_(std::move(strand)),
      broker_(std::move(broker)),
      handlers_(std::move(handlers)),
      tick_timer_(strand_),
      retry_timer_(strand_),
      backoff_(kFirstBackoff),
      keepalive_s_(session.keepalive_s) {
  init_library();
  client_ = mosquitto_new(session.client_id.c_str(), true, this);
  if (client_ == nullptr)
    throw std::runtime_error("MQTT: cannot make a client");
  mosquitto_connect_callback_set(client_, &MqttLink::on_connect);
  mosquitto_message_callback_set(client_, &MqttLink::on_message);
  mosquitto_publish_callback_set(client_, &MqttLink::on_publish);
  // No Nagle: a state sent right after a visualization would wait for the broker's delayed ACK (40 ms).
  require(mosquitto_int_option(client_, MOSQ_OPT_TCP_NODELAY, 1), "TCP_NODELAY");
  if (!session.will_topic.empty()) {
    require(
        mosquitto_will_set(client_, session.will_topic.c_str(), static_cast<int>(session.will_payload.size()),
                           session.will_payload.data(), 1, true),
        "the last will");
  }
  if (!session.username.empty())
    require(mosquitto_username_pw_set(client_, session.username.c_str(), session.password.c_str()),
            "the login");
  if (broker_.tls) {
    const char* ca_file = session.ca_file.empty() ? nullptr : session.ca_file.c_str();
    const char* ca_path = session.ca_file.empty() ? "/etc/ssl/certs" : nullptr;
    require(mosquitto_tls_set(client_, ca_file, ca_path, nullptr, nullptr, nullptr), "TLS");
  }
}

MqttLink::~MqttLink() {
  if (socket_)
    socket_->close();  // our duplicate; mosquitto_destroy closes its own
  mosquitto_destroy(client_);
}

void MqttLink::start() {
  boost::asio::post(strand_, [self = shared_from_this()] {
    self->connect();
    self->tick();
  });
}

void MqttLink::connect() {
  if (stopped_)
    return;
  // A name is looked up here, on the event loop (getaddrinfo): an address or a name in /etc/hosts at once.
  // The TCP connect itself does not block; the socket's first writability finishes it.
  const int result = mosquitto_connect_async(client_, broker_.host.c_str(), broker_.port, keepalive_s_);
  if (result != MOSQ_ERR_SUCCESS) {
    spdlog::warn("MQTT: cannot connect to {}:{}: {}", broker_.host, broker_.port,
                 result == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(result));
    reconnect_later();
    return;
  }
  watch_socket();
}

void MqttLink::reconnect_later() {
  drop_connection();
  if (stopped_)
    return;
  retry_timer_.expires_after(backoff_);
  retry_timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
    if (!error)
      self->connect();
  });
  backoff_ = std::min(backoff_ * 2, kLongestBackoff);
}

void MqttLink::watch_socket() {
  const int descriptor = mosquitto_socket(client_);
  const int copy = descriptor >= 0 ? ::dup(descriptor) : -1;
  if (copy < 0) {
    reconnect_later();
    return;
  }
  socket_.emplace(strand_, copy);
  wait_readable();
  wait_writable();
}

void MqttLink::wait_readable() {
  if (!socket_ || reading_)
    return;
  reading_ = true;
  socket_->async_wait(boost::asio::posix::descriptor_base::wait_read,
                      [self = shared_from_this()](boost::system::error_code error) {
                        self->reading_ = false;
                        if (error || !self->socket_)
                          return;
                        if (!self->check(mosquitto_loop_read(self->client_, 1), "read"))
                          return;
                        self->wait_readable();
                        self->wait_writable();
                      });
}

void MqttLink::wait_writable() {
  if (!socket_ || writing_ || !mosquitto_want_write(client_))
    return;
  writing_ = true;
  socket_->async_wait(boost::asio::posix::descriptor_base::wait_write,
                      [self = shared_from_this()](boost::system::error_code error) {
                        self->writing_ = false;
                        if (error || !self->socket_)
                          return;
                        if (!self->check(mosquitto_loop_write(self->client_, 1), "write"))
                          return;
                        self->wait_writable();
                      });
}

void MqttLink::tick() {
  if (stopped_)
    return;
  if (socket_ && check(mosquitto_loop_misc(client_), "keepalive"))
    wait_writable();  // a ping
  tick_timer_.expires_after(kTickPeriod);
  tick_timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
    if (!error)
      self->tick();
  });
}

bool MqttLink::check(int result, const char* what) {
  if (result == MOSQ_ERR_SUCCESS && mosquitto_socket(client_) >= 0)
    return true;
  if (connected_ || result != MOSQ_ERR_SUCCESS) {
    spdlog::warn("MQTT: the connection to {}:{} ended ({}: {}); connecting again in {:.1f} s", broker_.host,
                 broker_.port, what,
                 result == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(result),
                 std::chrono::duration<double>(backoff_).count());
  }
  reconnect_later();
  return false;
}

void MqttLink::drop_connection() {
  connected_ = false;
  if (socket_) {
    socket_->close();  // cancels the waits; their handlers see no socket
    socket_.reset();
  }
}

bool MqttLink::publish(const std::string& topic, std::string_view payload, int qos, bool retain) {
  if (!connected_)
    return false;
  const int result = mosquitto_publish(client_, nullptr, topic.c_str(), static_cast<int>(payload.size()),
                                       payload.data(), qos, retain);
  if (result != MOSQ_ERR_SUCCESS) {
    spdlog::warn("MQTT: cannot publish on {}: {}", topic, mosquitto_strerror(result));
    return false;
  }
  wait_writable();  // what the socket did not take at once
  return true;
}

bool MqttLink::subscribe(const std::string& topic, int qos) {
  if (!connected_)
    return false;
  const int result = mosquitto_subscribe(client_, nullptr, topic.c_str(), qos);
  wait_writable();
  return result == MOSQ_ERR_SUCCESS;
}

void MqttLink::close(const std::string& topic, const std::string& payload,
                     std::chrono::milliseconds timeout) {
  stopped_ = true;
  retry_timer_.cancel();
  tick_timer_.cancel();
  if (!connected_) {
    drop_connection();
    return;
  }
  // The event loop has stopped: nothing else calls into libmosquitto now; its own loop sends and waits.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const auto remaining_ms = [&deadline] {
    return static_cast<int>(std::max<std::int64_t>(
        0, std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now())
               .count()));
  };
  if (mosquitto_publish(client_, &last_mid_, topic.c_str(), static_cast<int>(payload.size()), payload.data(),
                        1, true) == MOSQ_ERR_SUCCESS) {
    while (!last_acknowledged_ && remaining_ms() > 0)
      if (mosquitto_loop(client_, std::min(remaining_ms(), 100), 1) != MOSQ_ERR_SUCCESS)
        break;
  }
  mosquitto_disconnect(client_);
  while (mosquitto_want_write(client_) && mosquitto_socket(client_) >= 0 && remaining_ms() > 0)
    if (mosquitto_loop(client_, std::min(remaining_ms(), 100), 1) != MOSQ_ERR_SUCCESS)
      break;
  drop_connection();
}

void MqttLink::on_connect(struct mosquitto* /*client*/, void* self, int code) {
  auto* link = static_cast<MqttLink*>(self);
  if (code != 0) {
    spdlog::warn("MQTT: {}:{} refused the session: {}", link->broker_.host, link->broker_.port,
                 mosquitto_connack_string(code));
    return;  // the broker closes the connection; the next read sees it
  }
  spdlog::info("MQTT: connected to {}:{}", link->broker_.host, link->broker_.port);
  link->connected_ = true;
  link->backoff_ = kFirstBackoff;
  if (link->handlers_.connected)
    link->handlers_.connected();
}

void MqttLink::on_message(struct mosquitto* /*client*/, void* self, const struct mosquitto_message* message) {
  auto* link = static_cast<MqttLink*>(self);
  if (link->handlers_.message && message->topic != nullptr) {
    const std::string_view payload(static_cast<const char*>(message->payload),
                                   static_cast<std::size_t>(std::max(0, message->payloadlen)));
    link->handlers_.message(message->topic, payload);
  }
}

void MqttLink::on_publish(struct mosquitto* /*client*/, void* self, int mid) {
  auto* link = static_cast<MqttLink*>(self);
  if (mid == link->last_mid_)
    link->last_acknowledged_ = true;
}

}  // namespace strata::fleet

#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "server/fleet/broker_address.hpp"

struct mosquitto;
struct mosquitto_message;

namespace strata::fleet {

/// Who the link logs in as and what the broker says for it when it goes without a word.
struct MqttSession {
  std::string client_id;
  std::string username;  ///< empty: none
  std::string password;
  std::string ca_file;  ///< TLS: the broker's CA (PEM); empty: the system's CAs
  std::string will_topic;
  std::string will_payload;  ///< published retained with QoS 1 by the broker when the link breaks
  int keepalive_s = 10;      ///< a silent broker is noticed after 1.5 times this
};

/// One MQTT client (libmosquitto, MQTT 3.1.1) on the server's event loop: the socket's readiness through
/// Asio (a duplicate of mosquitto's descriptor, so Asio and libmosquitto each close their own), keepalive
/// on a timer, and when the connection fails or breaks, a new one after a backoff of 0.5 s doubling to
/// 16 s. Every call into libmosquitto runs on one strand; the handlers run on it too, and so must the
/// callers of publish() and subscribe().
class MqttLink : public std::enable_shared_from_this<MqttLink> {
 public:
  struct Handlers {
    std::function<void()> connected;  ///< after every CONNACK that accepted the session (subscribe here)
    std::function<void(std::string_view topic, std::string_view payload)> message;
  };
  using Strand = boost::asio::strand<boost::asio::io_context::executor_type>;

  /// Sets the session up (TLS and credentials included); throws on what libmosquitto refuses.
  MqttLink(Strand strand, BrokerAddress broker, const MqttSession& session, Handlers handlers);
  ~MqttLink();
  MqttLink(const MqttLink&) = delete;
  MqttLink& operator=(const MqttLink&) = delete;

  /// Starts connecting (on the strand).
  void start();
  /// On the strand: false while there is no accepted session (the message is then not sent).
  bool publish(const std::string& topic, std::string_view payload, int qos, bool retain);
  bool subscribe(const std::string& topic, int qos);
  [[nodiscard]] bool connected() const { return connected_; }
  [[nodiscard]] const Strand& strand() const { return strand_; }

  /// After the event loop has stopped: publishes `payload` on `topic` (QoS 1, retained), disconnects
  /// cleanly and waits at most `timeout` for the broker to have both.
  void close(const std::string& topic, const std::string& payload, std::chrono::milliseconds timeout);

 private:
  void connect();
  void reconnect_later();
  void watch_socket();
  void wait_readable();
  void wait_writable();
  void tick();
  /// A loop call's result: on failure the connection is over.
  bool check(int result, const char* what);
  void drop_connection();

  static void on_connect(struct mosquitto* client, void* self, int code);
  static void on_message(struct mosquitto* client, void* self, const struct mosquitto_message* message);
  static void on_publish(struct mosquitto* client, void* self, int mid);

  Strand strand_;
  BrokerAddress broker_;
  Handlers handlers_;
  struct mosquitto* client_ = nullptr;
  std::optional<boost::asio::posix::stream_descriptor> socket_;  // a dup() of mosquitto's
  boost::asio::steady_timer tick_timer_;
  boost::asio::steady_timer retry_timer_;
  std::chrono::milliseconds backoff_;
  int keepalive_s_;
  bool have_session_ = false;  // mosquitto_connect_async succeeded once: reconnect from now on
  bool connected_ = false;     // CONNACK accepted
  bool reading_ = false;
  bool writing_ = false;
  bool stopped_ = false;
  int last_mid_ = -1;  // close(): the OFFLINE message's id
  bool last_acknowledged_ = false;
};

}  // namespace strata::fleet

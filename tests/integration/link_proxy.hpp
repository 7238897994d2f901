#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace strata::testing {

/// What the link between a client and the server does to the bytes that cross it.
struct LinkConditions {
  std::chrono::milliseconds delay{0};  ///< one way, each direction
  double bytes_per_second = 0.0;       ///< each direction; 0: no limit
  /// With a rate: bytes the link holds besides those on the wire (an access point's queue). Beyond it the
  /// proxy stops reading, so the backlog waits in the sender's socket, as it does behind a real slow
  /// link, where the sender can see and bound it.
  std::size_t queue_bytes = 8 * 1024;
};

/// A TCP proxy on loopback that stands for a poor Wi-Fi link between clients and the server: it delays what
/// crosses it, limits its rate, and can go down. During an outage nothing crosses, but nothing is lost
/// either: what was sent waits and crosses when the link returns, as TCP's retransmissions deliver it, all
/// at once. With a rate, the proxy reads only as fast as the link carries (see LinkConditions::queue_bytes).
/// Clients connect to port(); each connection gets its own pair of pumps. A test helper (issue 59).
class LinkProxy {
 public:
  LinkProxy(std::uint16_t server_port, LinkConditions conditions = {});
  ~LinkProxy();
  LinkProxy(const LinkProxy&) = delete;
  LinkProxy& operator=(const LinkProxy&) = delete;

  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// Down: nothing crosses in either direction until up again.
  void set_down(bool down) { down_.store(down); }

 private:
  void accept_loop();
  void pump(int from, int to);

  std::uint16_t server_port_;
  LinkConditions conditions_;
  int listener_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> down_{false};
  std::atomic<bool> stopping_{false};
  std::mutex mutex_;
  std::vector<int> sockets_;
  std::vector<std::thread> threads_;
  std::thread acceptor_;
};

}  // namespace strata::testing

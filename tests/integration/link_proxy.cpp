#include "integration/link_proxy.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <deque>
#include <limits>
#include <stdexcept>
#include <string>

namespace strata::testing {
namespace {

using Clock = std::chrono::steady_clock;

/// `receive_buffer` > 0: the socket's receive buffer, set before connecting so the window is that small.
int connect_to(std::uint16_t port, int receive_buffer) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (receive_buffer > 0) {
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof(receive_buffer));
    // Wi-Fi's segment size, not loopback's 64 KiB: the window then opens a segment at a time as the link
    // drains, as it does behind a real link, instead of in bursts of half the buffer.
    const int segment = 1448;
    ::setsockopt(fd, IPPROTO_TCP, TCP_MAXSEG, &segment, sizeof(segment));
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    ::close(fd);
    return -1;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return fd;
}

/// Bytes read at one time, and when they may be delivered.
struct Chunk {
  std::string bytes;
  Clock::time_point due;
};

}  // namespace

LinkProxy::LinkProxy(std::uint16_t server_port, LinkConditions conditions)
    : server_port_(server_port), conditions_(conditions) {
  listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
  const int one = 1;
  ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof(address);
  if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      ::listen(listener_, 16) != 0 ||
      ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    throw std::runtime_error("link proxy: cannot listen on loopback");
  }
  port_ = ntohs(address.sin_port);
  acceptor_ = std::thread([this] { accept_loop(); });
}

LinkProxy::~LinkProxy() {
  stopping_.store(true);
  acceptor_.join();
  for (auto& thread : threads_)
    thread.join();
  for (const int fd : sockets_)
    ::close(fd);
  ::close(listener_);
}

void LinkProxy::accept_loop() {
  while (!stopping_.load()) {
    pollfd waiting{listener_, POLLIN, 0};
    if (::poll(&waiting, 1, 20) <= 0)
      continue;
    const int client = ::accept(listener_, nullptr, nullptr);
    if (client < 0)
      continue;
    const int one = 1;
    ::setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    // With a rate, the server's bytes must wait in the server's socket, not in loopback's large buffers.
    const int server = connect_to(server_port_, conditions_.bytes_per_second > 0.0 ? 4096 : 0);
    if (server < 0) {
      ::close(client);
      continue;
    }
    std::lock_guard lock(mutex_);
    sockets_.push_back(client);
    sockets_.push_back(server);
    threads_.emplace_back([this, client, server] { pump(client, server); });
    threads_.emplace_back([this, client, server] { pump(server, client); });
  }
}

void LinkProxy::pump(int from, int to) {
  std::deque<Chunk> in_flight;
  std::size_t held = 0;  // bytes in in_flight
  // What the link holds at most: what is on the wire (rate x delay) and its queue. No rate: no bound.
  const std::size_t capacity =
      conditions_.bytes_per_second > 0.0
          ? static_cast<std::size_t>(conditions_.bytes_per_second *
                                     std::chrono::duration<double>(conditions_.delay).count()) +
                conditions_.queue_bytes
          : std::numeric_limits<std::size_t>::max();
  bool from_open = true;
  double credit = 0.0;  // bytes the rate limit allows now
  auto last_credit = Clock::now();
  while (!stopping_.load() && (from_open || !in_flight.empty())) {
    if (from_open && held < capacity) {
      pollfd readable{from, POLLIN, 0};
      if (::poll(&readable, 1, 5) > 0) {
        char buffer[16384];
        const ssize_t n = ::read(from, buffer, std::min(sizeof(buffer), capacity - held));
        if (n <= 0) {
          from_open = false;
        } else {
          in_flight.push_back(
              {std::string(buffer, static_cast<std::size_t>(n)), Clock::now() + conditions_.delay});
          held += static_cast<std::size_t>(n);
        }
      }
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const auto now = Clock::now();
    if (conditions_.bytes_per_second > 0.0) {
      credit = std::min(
          credit + std::chrono::duration<double>(now - last_credit).count() * conditions_.bytes_per_second,
          conditions_.bytes_per_second * 0.05);  // bursts of at most 50 ms of the rate
    }
    last_credit = now;
    // An outage holds everything; afterwards what waited is due at once.
    while (!down_.load() && !in_flight.empty() && in_flight.front().due <= now) {
      Chunk& chunk = in_flight.front();
      std::size_t allowed = chunk.bytes.size();
      if (conditions_.bytes_per_second > 0.0)
        allowed = std::min(allowed, static_cast<std::size_t>(std::max(credit, 0.0)));
      if (allowed == 0)
        break;
      const ssize_t written = ::send(to, chunk.bytes.data(), allowed, MSG_NOSIGNAL);
      if (written <= 0) {
        in_flight.clear();
        from_open = false;
        break;
      }
      credit -= static_cast<double>(written);
      held -= static_cast<std::size_t>(written);
      chunk.bytes.erase(0, static_cast<std::size_t>(written));
      if (chunk.bytes.empty())
        in_flight.pop_front();
    }
  }
  ::shutdown(to, SHUT_WR);
}

}  // namespace strata::testing

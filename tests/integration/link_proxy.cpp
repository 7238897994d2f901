#include "integration/link_proxy.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <deque>
#include <stdexcept>
#include <string>

namespace strata::testing {
namespace {

using Clock = std::chrono::steady_clock;

int connect_to(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
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
    const int server = connect_to(server_port_);
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
  bool from_open = true;
  double credit = 0.0;  // bytes the rate limit allows now
  auto last_credit = Clock::now();
  while (!stopping_.load() && (from_open || !in_flight.empty())) {
    if (from_open) {
      pollfd readable{from, POLLIN, 0};
      if (::poll(&readable, 1, 5) > 0) {
        char buffer[16384];
        const ssize_t n = ::read(from, buffer, sizeof(buffer));
        if (n <= 0)
          from_open = false;
        else
          in_flight.push_back(
              {std::string(buffer, static_cast<std::size_t>(n)), Clock::now() + conditions_.delay});
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
      chunk.bytes.erase(0, static_cast<std::size_t>(written));
      if (chunk.bytes.empty())
        in_flight.pop_front();
    }
  }
  ::shutdown(to, SHUT_WR);
}

}  // namespace strata::testing

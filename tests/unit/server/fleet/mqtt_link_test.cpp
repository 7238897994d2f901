// The MQTT link's socket (issue 61): Nagle off, so a state sent right after a visualization does not wait
// for the broker's delayed ACK (40 ms on Linux; docs/benchmarks.md, "The fleet link"). A plain TCP listener
// stands in for the broker: only the link's connecting socket is looked at, no MQTT is spoken.
#include "server/fleet/mqtt_link.hpp"

#include <dirent.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <boost/asio/ip/tcp.hpp>
#include <cstdlib>
#include <optional>

namespace strata::fleet {
namespace {

/// This process's descriptor connected to 127.0.0.1:`peer_port` from `local_port`, if any.
std::optional<int> socket_between(unsigned short local_port, unsigned short peer_port) {
  DIR* descriptors = ::opendir("/proc/self/fd");
  if (descriptors == nullptr)
    return std::nullopt;
  std::optional<int> found;
  while (const dirent* entry = ::readdir(descriptors)) {
    const int fd = std::atoi(entry->d_name);
    sockaddr_in local{};
    sockaddr_in peer{};
    socklen_t local_size = sizeof local;
    socklen_t peer_size = sizeof peer;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_size) == 0 &&
        ::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &peer_size) == 0 &&
        local.sin_family == AF_INET && ntohs(local.sin_port) == local_port &&
        ntohs(peer.sin_port) == peer_port)
      found = fd;
  }
  ::closedir(descriptors);
  return found;
}

TEST(MqttLink, ConnectsWithNagleOff) {
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor broker(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  const unsigned short broker_port = broker.local_endpoint().port();
  auto link =
      std::make_shared<MqttLink>(boost::asio::make_strand(io), BrokerAddress{"127.0.0.1", broker_port},
                                 MqttSession{.client_id = "nodelay-test"}, MqttLink::Handlers{});
  boost::asio::ip::tcp::socket accepted(io);
  broker.async_accept(accepted, [&io](boost::system::error_code) { io.stop(); });
  link->start();
  io.run();
  ASSERT_TRUE(accepted.is_open());
  const auto fd = socket_between(accepted.remote_endpoint().port(), broker_port);
  ASSERT_TRUE(fd) << "the link's socket is not found";
  int nodelay = 0;
  socklen_t size = sizeof nodelay;
  ASSERT_EQ(::getsockopt(*fd, IPPROTO_TCP, TCP_NODELAY, &nodelay, &size), 0);
  EXPECT_NE(nodelay, 0) << "Nagle is on: small messages wait for the broker's delayed ACK";
}

}  // namespace
}  // namespace strata::fleet

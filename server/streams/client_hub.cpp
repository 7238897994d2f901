#include "server/streams/client_hub.hpp"

#include <algorithm>
#include <vector>

namespace strata::streams {

void ClientHub::join(const std::shared_ptr<ClientConnection>& client) {
  std::lock_guard lock(mutex_);
  clients_.emplace(client.get(), client);
}

void ClientHub::leave(const ClientConnection* client) {
  std::lock_guard lock(mutex_);
  clients_.erase(client);
}

void ClientHub::broadcast(const OutgoingMessage& message) {
  // Copy the list under the lock and send outside it, so a client's send never holds up join/leave.
  std::vector<std::weak_ptr<ClientConnection>> targets;
  {
    std::lock_guard lock(mutex_);
    targets.reserve(clients_.size());
    for (const auto& [key, client] : clients_)
      targets.push_back(client);
  }
  for (const auto& weak : targets) {
    if (auto client = weak.lock())
      client->send(message);
  }
}

std::vector<ClientStats> ClientHub::stats() const {
  std::vector<std::shared_ptr<ClientConnection>> clients;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [key, client] : clients_) {
      if (auto alive = client.lock())
        clients.push_back(std::move(alive));
    }
  }
  std::vector<ClientStats> stats;
  stats.reserve(clients.size());
  for (const auto& client : clients)
    stats.push_back(client->stats());
  std::ranges::sort(stats, {}, &ClientStats::id);
  return stats;
}

std::size_t ClientHub::size() const {
  std::lock_guard lock(mutex_);
  return clients_.size();
}

}  // namespace strata::streams

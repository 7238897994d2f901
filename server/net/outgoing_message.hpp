#pragma once

#include <memory>
#include <string>

namespace strata::net {

/// One message on its way to clients. The payload is encoded once and shared by every client's queue.
struct OutgoingMessage {
  std::shared_ptr<const std::string> payload;
  bool binary = false;
  /// Messages with the same non-empty key supersede each other while unsent: a client that lags
  /// gets the newest pose, not a backlog of stale ones.
  std::string coalesce_key;

  static OutgoingMessage text(std::string body, std::string coalesce_key = {}) {
    return {std::make_shared<const std::string>(std::move(body)), false, std::move(coalesce_key)};
  }
};

}  // namespace strata::net

#pragma once

#include <array>
#include <boost/asio/ip/address.hpp>
#include <cstddef>
#include <map>
#include <mutex>
#include <optional>

namespace strata::net {

/// At most `max` connections at once from one IP address, whatever they are (an HTTP request, an idle
/// keep-alive, a WebSocket client): one host cannot take every place and lock the others out (issue 59).
/// A connection holds a Slot from its accept until it closes. Thread-safe; a Slot must not outlive its
/// limit. IPv4 and its IPv6-mapped form count as one address.
class AddressLimit {
 public:
  using Key = std::array<unsigned char, 16>;

  /// One place for one address, given back when destroyed.
  class Slot {
   public:
    Slot(Slot&& other) noexcept : limit_(other.limit_), key_(other.key_) { other.limit_ = nullptr; }
    Slot& operator=(Slot&&) = delete;
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;
    ~Slot() {
      if (limit_ != nullptr)
        limit_->release(key_);
    }

   private:
    friend class AddressLimit;
    Slot(AddressLimit* limit, const Key& key) : limit_(limit), key_(key) {}
    AddressLimit* limit_;
    Key key_;
  };

  explicit AddressLimit(std::size_t max) : max_(max) {}
  AddressLimit(const AddressLimit&) = delete;
  AddressLimit& operator=(const AddressLimit&) = delete;

  /// A place for `address`, or nullopt when it holds `max` already.
  [[nodiscard]] std::optional<Slot> try_acquire(const boost::asio::ip::address& address) {
    const Key key = key_of(address);
    std::lock_guard lock(mutex_);
    std::size_t& held = held_[key];
    if (held >= max_)
      return std::nullopt;
    ++held;
    return Slot(this, key);
  }

  [[nodiscard]] std::size_t max() const { return max_; }
  /// Addresses holding at least one place now.
  [[nodiscard]] std::size_t addresses() const {
    std::lock_guard lock(mutex_);
    return held_.size();
  }

 private:
  static Key key_of(const boost::asio::ip::address& address) {
    if (address.is_v4())
      return boost::asio::ip::make_address_v6(boost::asio::ip::v4_mapped, address.to_v4()).to_bytes();
    return address.to_v6().to_bytes();
  }
  void release(const Key& key) {
    std::lock_guard lock(mutex_);
    const auto held = held_.find(key);
    if (held != held_.end() && --held->second == 0)
      held_.erase(held);  // the map holds only the addresses connected now
  }

  std::size_t max_;
  mutable std::mutex mutex_;
  std::map<Key, std::size_t> held_;
};

}  // namespace strata::net

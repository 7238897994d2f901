#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/points/voxel_key.hpp"

namespace strata {

/// Voxel key -> 32-bit value, as one flat array probed linearly (power-of-two capacity, at most half
/// full). What the voxel grids use instead of std::unordered_map, which allocates a node per key: thinning
/// an 80k-point scan went from 190 to ~40 instructions per point (tests/bench/registration_bench.cpp).
class VoxelKeyMap {
 public:
  explicit VoxelKeyMap(std::size_t expected = 16) { rehash(capacity_for(expected)); }

  /// The value stored under `key`, or `value` stored under it if the key is new; .second tells which.
  std::pair<std::uint32_t, bool> try_emplace(VoxelKey key, std::uint32_t value) {
    std::size_t slot = home(key);
    while (slots_[slot].key != kEmpty) {
      if (slots_[slot].key == key)
        return {slots_[slot].value, false};
      slot = (slot + 1) & mask_;
    }
    slots_[slot] = {key, value};
    if (++size_ * 2 > slots_.size())
      rehash(slots_.size() * 2);
    return {value, true};
  }

  /// A pointer to the value under `key`, or nullptr.
  [[nodiscard]] const std::uint32_t* find(VoxelKey key) const {
    for (std::size_t slot = home(key); slots_[slot].key != kEmpty; slot = (slot + 1) & mask_) {
      if (slots_[slot].key == key)
        return &slots_[slot].value;
    }
    return nullptr;
  }

  /// Asks the cache for the slot where `key` is looked for: a map of a few hundred thousand voxels is
  /// tens of megabytes, and a lookup started some keys ahead no longer waits for memory.
  void prefetch(VoxelKey key) const { __builtin_prefetch(&slots_[home(key)]); }

  [[nodiscard]] std::size_t size() const { return size_; }

  /// Empties the map, keeping its capacity.
  void clear() {
    for (Slot& slot : slots_)
      slot.key = kEmpty;
    size_ = 0;
  }

 private:
  // Packed keys use 63 bits (3 x 21), so the all-ones key never occurs.
  static constexpr VoxelKey kEmpty = ~VoxelKey{0};
  struct Slot {
    VoxelKey key;
    std::uint32_t value;
  };

  static std::size_t capacity_for(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected)
      capacity *= 2;
    return capacity;
  }
  [[nodiscard]] std::size_t home(VoxelKey key) const {
    // Fibonacci hashing: the top bits of the product mix all of the key's bits.
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_);
  }
  void rehash(std::size_t capacity) {
    std::vector<Slot> old(capacity, Slot{kEmpty, 0});
    old.swap(slots_);
    mask_ = capacity - 1;
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c /= 2)
      --shift_;
    size_ = 0;
    for (const Slot& slot : old) {
      if (slot.key != kEmpty)
        try_emplace(slot.key, slot.value);
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace strata

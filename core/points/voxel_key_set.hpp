#pragma once

#include <cstddef>
#include <vector>

#include "core/points/voxel_key.hpp"

namespace strata {

/// A set of voxel keys, as one flat array probed linearly (power-of-two capacity, at most half full):
/// VoxelKeyMap without the values, for the grids that only ask whether a voxel was reached. A slot is the
/// key alone, 8 bytes instead of 16, so the array streams through half the cache.
class VoxelKeySet {
 public:
  explicit VoxelKeySet(std::size_t expected = 16) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected)
      capacity *= 2;
    reset(capacity);
  }

  /// Adds `key`; true if it was not in the set yet.
  bool insert(VoxelKey key) {
    std::size_t slot = home(key);
    while (slots_[slot] != kEmpty) {
      if (slots_[slot] == key)
        return false;
      slot = (slot + 1) & mask_;
    }
    slots_[slot] = key;
    if (++size_ * 2 > slots_.size())
      grow();
    return true;
  }

  [[nodiscard]] std::size_t size() const { return size_; }

 private:
  // Packed keys use 63 bits (3 x 21), so the all-ones key never occurs.
  static constexpr VoxelKey kEmpty = ~VoxelKey{0};

  [[nodiscard]] std::size_t home(VoxelKey key) const {
    // Fibonacci hashing, as VoxelKeyMap: the top bits of the product mix all of the key's bits.
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_);
  }
  void reset(std::size_t capacity) {
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c /= 2)
      --shift_;
    size_ = 0;
  }
  void grow() {
    std::vector<VoxelKey> old;
    old.swap(slots_);
    reset(old.size() * 2);
    for (const VoxelKey key : old) {
      if (key != kEmpty)
        insert(key);
    }
  }

  std::vector<VoxelKey> slots_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace strata

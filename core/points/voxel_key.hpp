#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace strata {

/// The integer cell of a cubic voxel grid that a point falls into, packed into one 64-bit key (21 bits per
/// axis) so it hashes and compares as a single integer. Cells span +-2^20 voxels per axis: +-52 km at
/// 5 cm voxels, far beyond any scan.
using VoxelKey = std::uint64_t;

/// floor(value) as an int, for values within int's range: a truncation and a correction, where std::floor
/// is a library call on the baseline x86-64 instruction set (no SSE4.1 rounding).
[[nodiscard]] inline int floor_to_int(double value) {
  const int truncated = static_cast<int>(value);
  return truncated - (value < static_cast<double>(truncated) ? 1 : 0);
}

[[nodiscard]] inline Eigen::Vector3i voxel_cell(const Eigen::Vector3d& point, double inverse_voxel_size) {
  return {floor_to_int(point.x() * inverse_voxel_size), floor_to_int(point.y() * inverse_voxel_size),
          floor_to_int(point.z() * inverse_voxel_size)};
}

[[nodiscard]] inline VoxelKey voxel_key(const Eigen::Vector3i& cell) {
  constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  constexpr int kOffset = 1 << 20;
  const auto axis = [](int value) { return static_cast<std::uint64_t>(value + kOffset) & kMask; };
  return (axis(cell.x()) << 42) | (axis(cell.y()) << 21) | axis(cell.z());
}

/// Spreads the packed key's bits before an unordered container takes them modulo its bucket count
/// (the identity hash would put whole planes of cells into a few buckets).
struct VoxelKeyHash {
  std::size_t operator()(VoxelKey key) const noexcept {
    key ^= key >> 33;
    key *= 0xff51afd7ed558ccdULL;
    key ^= key >> 33;
    return static_cast<std::size_t>(key);
  }
};

}  // namespace strata

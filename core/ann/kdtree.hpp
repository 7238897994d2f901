#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/ann/neighbor.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// A static kd-tree over a point cloud it owns. Chosen over a voxel hash and the thesis octree by
/// measurement (tests/bench/registration_bench.cpp --search): it answers bounded nearest queries at any
/// radius, which the coarse-to-fine ICP needs. Hand-written for 3D points in place of nanoflann, by
/// measurement (the same bench, and instruction counts of whole registrations): the points copied as floats
/// in leaf order, cells split in the middle, and a search without recursion.
class KdTree {
 public:
  explicit KdTree(PointCloud points);

  /// The closest point within `max_distance` of `query`, if any. The bound prunes the search (the thesis's
  /// trimming: pairs farther apart than this are not correspondences at all).
  [[nodiscard]] std::optional<Neighbor> nearest(const Eigen::Vector3d& query, double max_distance) const;
  /// The closest point within `max_distance` of `query` and the runner-up, each if any. How far apart they
  /// are tells how far the query may move before its closest point can change (ICP's partner reuse).
  /// `hint`: the previous answer for a nearby query, if any (indices into points()); its points bound the
  /// search from the start.
  [[nodiscard]] NearestTwo nearest_two(const Eigen::Vector3d& query, double max_distance,
                                       const NearestTwo& hint = {}) const;
  /// The `k` closest points (fewer if the cloud is smaller), nearest first.
  [[nodiscard]] std::vector<Neighbor> k_nearest(const Eigen::Vector3d& query, std::size_t k) const;
  /// The same into `out`, whose memory is reused from call to call.
  void k_nearest(const Eigen::Vector3d& query, std::size_t k, std::vector<Neighbor>& out) const;
  /// The `k` closest within `max_distance` (fewer if fewer lie within it), nearest first, into `out`.
  void k_nearest(const Eigen::Vector3d& query, std::size_t k, double max_distance,
                 std::vector<Neighbor>& out) const;

  [[nodiscard]] const PointCloud& points() const { return points_; }
  [[nodiscard]] std::size_t size() const { return points_.size(); }

 private:
  /// A point relative to origin_, in single precision (half the memory to stream through), with its index
  /// in points_ as a float's bits: four floats, loaded as one vector.
  struct Leaf {
    float x, y, z;
    float tag;
    [[nodiscard]] std::uint32_t index() const { return std::bit_cast<std::uint32_t>(tag); }
  };
  /// Internal nodes split along `axis` (0-2): the left child follows the node, the right one is at
  /// `first`; `low` and `high` are the largest coordinate on the left and the smallest on the right. Leaves
  /// (axis == kLeaf) hold `count` points from leaves_[first].
  struct Node {
    float low = 0.0F;
    float high = 0.0F;
    std::uint32_t first = 0;
    std::uint16_t axis = 0;
    std::uint16_t count = 0;
  };
  static constexpr std::uint16_t kLeaf = 3;
  struct Box {
    std::array<float, 3> low;
    std::array<float, 3> high;
  };
  std::uint32_t build(std::uint32_t begin, std::uint32_t end, const Box& cell, const Box& points, int depth);
  [[nodiscard]] Box bounds(std::uint32_t begin, std::uint32_t end) const;
  /// Partitions leaves_[begin, end) at `cut` along `axis` (low <= cut <= high, the points' extremes there,
  /// low < high), returns where the upper half starts and sets the halves' bounds.
  std::uint32_t divide(std::uint32_t begin, std::uint32_t end, int axis, float cut, float low, float high,
                       Box& lower, Box& upper);
  template <class Coordinate>
  std::uint32_t divide_along(std::uint32_t begin, std::uint32_t end, float cut, float low, float high,
                             Coordinate coordinate, Box& lower, Box& upper);
  /// libstdc++ std::partition's own swaps (the same tree, point for point), bounding each half as it goes:
  /// one pass over the points instead of two.
  template <class Below>
  Leaf* partition(Leaf* first, Leaf* last, Below below, Box& lower, Box& upper);
  template <class Result>
  void search(const float* query, Result& result) const;
  template <class Result>
  static void scan(const Leaf* first, std::uint32_t count, const float* query, Result& result);
  void relative(const Eigen::Vector3d& query, float* out) const;

  PointCloud points_;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  std::vector<Leaf> leaves_;
  std::vector<Node> nodes_;
  Box root_{};  ///< the points' bounding box, relative to origin_
};

}  // namespace strata

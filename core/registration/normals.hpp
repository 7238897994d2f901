#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/ann/growing_kdtree.hpp"

namespace strata {

/// Surface normals of a kd-tree's points, estimated on first use from the `k` nearest neighbours (the
/// eigenvector of their covariance with the smallest eigenvalue). Lazy because ICP only ever asks for the
/// normals of target points that some source point pairs with: a few thousand of a scan's points.
class LazyNormals {
 public:
  enum class State : std::uint8_t { kUnknown, kValid, kInvalid };
  /// What has been estimated so far, per point of the tree: handed to the next tree over the same points
  /// (a local map that grew), so they are not estimated again.
  struct Estimates {
    std::vector<Eigen::Vector3d> normals;
    std::vector<State> states;
  };

  /// `earlier`: estimates for the tree's first points, from an earlier tree over them (the rest are
  /// estimated on first use).
  explicit LazyNormals(const GrowingKdTree& tree, std::size_t k = 20, Estimates earlier = {});

  /// The unit normal at point `index`, or nullptr where the neighbourhood is no surface (too few
  /// neighbours, or as spread in its flattest direction as in the others: a corner or scatter).
  [[nodiscard]] const Eigen::Vector3d* at(std::size_t index);
  /// Estimates now, on up to `threads` threads, the normals at those of `indices` not known yet (each is
  /// estimated from the tree alone, so the order and the threads do not change it): at() then only looks
  /// them up. A registration's first pairing asks for thousands of normals at once.
  void estimate(std::span<const std::uint32_t> indices, unsigned threads);

  /// Moves the estimates out; the normals are then empty.
  [[nodiscard]] Estimates take() { return std::move(estimates_); }

 private:
  /// Estimates the normal at `index` into estimates_, with `neighbors` as scratch.
  void estimate_one(std::size_t index, std::vector<Neighbor>& neighbors);

  const GrowingKdTree* tree_;
  std::size_t k_;
  Estimates estimates_;
  std::vector<Neighbor> neighbors_;  // scratch, reused
};

}  // namespace strata

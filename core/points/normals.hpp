#pragma once

#include <cstdint>
#include <vector>

#include "core/ann/kdtree.hpp"

namespace strata {

/// Surface normals of a kd-tree's points, estimated on first use from the `k` nearest neighbours (the
/// eigenvector of their covariance with the smallest eigenvalue). Lazy because ICP only ever asks for the
/// normals of target points that some source point pairs with: a few thousand of a scan's points.
class LazyNormals {
 public:
  explicit LazyNormals(const KdTree& tree, std::size_t k = 20);

  /// The unit normal at point `index`, or nullptr where the neighbourhood is no surface (too few
  /// neighbours, or as spread in its flattest direction as in the others: a corner or scatter).
  [[nodiscard]] const Eigen::Vector3d* at(std::size_t index);

 private:
  enum class State : std::uint8_t { kUnknown, kValid, kInvalid };
  const KdTree* tree_;
  std::size_t k_;
  std::vector<Eigen::Vector3d> normals_;
  std::vector<State> states_;
  std::vector<Neighbor> neighbors_;  // scratch, reused
};

}  // namespace strata

#include "core/registration/normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "core/parallel/parallel_for.hpp"

namespace strata {
namespace {

/// Fewer unknown normals than this a thread are left to the caller's: a normal costs about 2 microseconds,
/// a thread's start about 30.
constexpr std::size_t kMinPerThread = 64;

}  // namespace

LazyNormals::LazyNormals(const GrowingKdTree& tree, std::size_t k, Estimates earlier)
    : tree_(&tree), k_(k), estimates_(std::move(earlier)) {
  estimates_.normals.resize(tree.size());
  estimates_.states.resize(tree.size(), State::kUnknown);
}

const Eigen::Vector3d* LazyNormals::at(std::size_t index) {
  if (estimates_.states[index] == State::kUnknown)
    estimate_one(index, neighbors_);
  return estimates_.states[index] == State::kValid ? &estimates_.normals[index] : nullptr;
}

void LazyNormals::estimate(std::span<const std::uint32_t> indices, unsigned threads) {
  std::vector<std::uint32_t> unknown;
  for (const std::uint32_t index : indices)
    if (estimates_.states[index] == State::kUnknown)
      unknown.push_back(index);
  // Each index once: two threads must not write one estimate.
  std::sort(unknown.begin(), unknown.end());
  unknown.erase(std::unique(unknown.begin(), unknown.end()), unknown.end());
  parallel_for(unknown.size(), threads, kMinPerThread, [&](std::size_t begin, std::size_t end) {
    std::vector<Neighbor> neighbors;
    for (std::size_t i = begin; i < end; ++i)
      estimate_one(unknown[i], neighbors);
  });
}

void LazyNormals::estimate_one(std::size_t index, std::vector<Neighbor>& neighbors) {
  State& state = estimates_.states[index];
  tree_->k_nearest(tree_->points()[index], k_, neighbors);
  state = State::kInvalid;
  if (neighbors.size() < 5)
    return;
  // One pass over the neighbours, relative to the point itself (no cancellation: they are within
  // centimetres of it), and the closed-form 3x3 eigensolver: half the instructions of two passes and
  // the iterative solver (the neighbour search aside), and the validity test below keeps only
  // well-separated eigenvalues, where the two agree.
  const Eigen::Vector3d& centre = tree_->points()[index];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double xx = 0.0, xy = 0.0, xz = 0.0, yy = 0.0, yz = 0.0, zz = 0.0;
  for (const Neighbor& n : neighbors) {
    const Eigen::Vector3d d = tree_->points()[n.index] - centre;
    sum += d;
    xx += d.x() * d.x();
    xy += d.x() * d.y();
    xz += d.x() * d.z();
    yy += d.y() * d.y();
    yz += d.y() * d.z();
    zz += d.z() * d.z();
  }
  const double count = static_cast<double>(neighbors.size());
  const Eigen::Vector3d mean = sum / count;
  Eigen::Matrix3d covariance;
  covariance << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  covariance -= count * mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  const Eigen::Vector3d& values = solver.eigenvalues();  // ascending
  // A surface is flat in one direction and spread in two: smallest spread well below the middle one,
  // and the middle one not negligible (k neighbours all on one scan line give a line, whose "normal"
  // is any direction across it).
  if (values(2) > 0.0 && values(0) < 0.3 * values(1) && values(1) > 0.05 * values(2)) {
    estimates_.normals[index] = solver.eigenvectors().col(0);
    state = State::kValid;
  }
}

}  // namespace strata

#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <vector>

namespace strata {

/// 6x6 information (inverse covariance) of a relative pose: translation x, y, z, then rotation about x,
/// y, z, both in the frame of the edge's `from` node. A direction nothing measured has zero information:
/// weak directions stay weak instead of being faked.
using PoseInformation = Eigen::Matrix<double, 6, 6>;

/// A measured relative pose between two nodes: where `to` is seen from `from` (from^-1 * to).
struct PoseGraphEdge {
  std::size_t from = 0;
  std::size_t to = 0;
  Eigen::Isometry3d measurement = Eigen::Isometry3d::Identity();
  PoseInformation information = PoseInformation::Identity();
  /// A loop closure: under a robust loss, so one wrong match cannot pull the whole map apart, and it may
  /// be dropped when it disagrees with the rest after optimizing (PoseGraph::optimize).
  bool loop = false;
};

/// Gravity seen by the robot (an inclinometer, the terrain under the wheels): which way is up in the
/// node's body frame as the sensor read it, with the standard deviation of its tilt. Anchors roll and
/// pitch, and so the height a tilt error would otherwise walk. The sensor's mounting error, a tilt fixed in
/// the body frame and the same for every reading, is estimated with the poses (PoseGraph::mounting_error).
struct AttitudePrior {
  std::size_t node = 0;
  Eigen::Vector3d up_in_body = Eigen::Vector3d::UnitZ();
  double sigma = 0.02;  ///< radians
};

struct PoseGraphOptions {
  int max_iterations = 50;
  /// A loop edge whose whitened residual (in standard deviations) is above this after optimizing is
  /// taken for a false match: it is dropped and the graph optimized again without it.
  double max_loop_residual = 5.0;
  /// How far the gravity sensor's mounting may be off, radians (standard deviation of the prior that holds
  /// the graph's estimate of it near zero); 0 holds it at its current value. One tilt shared by every
  /// attitude prior, fixed in the body frame: a map tilted by it would tilt one way driven out and the
  /// other way driven back, which the loops between the two forbid, so an out-and-back tells it (the IMU
  /// of docs/benchmarks.md, "The IMU's mounting error in the pose graph").
  double mounting_sigma = 0.01;
};

struct PoseGraphSummary {
  bool solved = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;
  std::size_t loops_dropped = 0;  ///< loop edges dropped as false matches in this call
};

/// Poses joined by relative measurements (odometry, scan matching, loop closures), optimized together
/// by nonlinear least squares (Ceres). The first node is held fixed: it defines the map frame.
class PoseGraph {
 public:
  /// Returns the new node's index; `pose` is its initial estimate.
  std::size_t add_node(const Eigen::Isometry3d& pose);
  void add_edge(const PoseGraphEdge& edge);
  void add_prior(const AttitudePrior& prior);

  /// Moves the estimates to the least-squares solution. Loop edges that disagree with the rest are
  /// dropped (PoseGraphOptions::max_loop_residual).
  PoseGraphSummary optimize(const PoseGraphOptions& options = {});

  [[nodiscard]] std::size_t size() const { return positions_.size(); }
  [[nodiscard]] Eigen::Isometry3d pose(std::size_t node) const;
  void set_pose(std::size_t node, const Eigen::Isometry3d& pose);
  [[nodiscard]] const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  /// The gravity sensor's mounting error as estimated: a rotation vector in the body frame (radians; z
  /// always 0, gravity cannot see a turn about it) that takes the body's up to where the sensor reads it.
  [[nodiscard]] Eigen::Vector3d mounting_error() const { return {mounting_.x(), mounting_.y(), 0.0}; }
  /// Where the next optimization starts from (an estimate from elsewhere, the scan path's).
  void set_mounting_error(const Eigen::Vector3d& mounting) { mounting_ = mounting.head<2>(); }
  [[nodiscard]] std::size_t loop_count() const;
  [[nodiscard]] std::size_t prior_count() const { return priors_.size(); }

  /// The whitened residual of an edge at the current estimates: how many standard deviations the
  /// estimates are from its measurement.
  [[nodiscard]] double residual(const PoseGraphEdge& edge) const;

 private:
  std::vector<Eigen::Vector3d> positions_;
  std::vector<Eigen::Quaterniond> rotations_;
  std::vector<PoseGraphEdge> edges_;
  std::vector<AttitudePrior> priors_;
  Eigen::Vector2d mounting_ = Eigen::Vector2d::Zero();  ///< about the body's x and y
};

}  // namespace strata

#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "core/ann/kdtree.hpp"
#include "core/points/normals.hpp"
#include "core/points/point_cloud.hpp"
#include "core/registration/fault_check.hpp"
#include "core/registration/icp.hpp"

namespace strata {

struct RegistrationOptions {
  double source_voxel_size = 0.3;   ///< metres; the source is thinned harder than the target (speed)
  double target_voxel_size = 0.05;  ///< metres
  double min_range = 0.3;           ///< drop returns closer than this to the sensor (the robot itself)
  /// Correspondence bounds, coarse to fine: ICP runs to convergence at each, so a guess that is off by more
  /// than the final (thesis) 0.25 m still finds its surfaces.
  std::vector<double> correspondence_schedule = {1.0, 0.25};
  IcpOptions icp;
  /// The MSE-change stop (m^2) of the last, finest stage; the coarse stages use icp.mse_change_threshold.
  /// Point-to-point ICP creeps the last centimetres in small steps that each change the MSE by less than
  /// the coarse threshold: stopping there left the far 3dtk pair (2 -> 0) at 6.8 cm / 0.69 deg from the
  /// reference, running on to this threshold brings it to 2.2 cm / 0.27 deg
  /// (tests/bench/registration_bench.cpp).
  double fine_mse_change_threshold = 2e-6;
  FaultLimits limits;
};

struct RegistrationResult {
  /// What to use: the refined transform if accepted, the guess if not. Maps source points into the target.
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d refined = Eigen::Isometry3d::Identity();  ///< ICP's answer, even when rejected
  std::size_t pairs = 0;                                      ///< final pairs within the last bound
  std::size_t source_points = 0;                              ///< after downsampling
  std::size_t target_points = 0;                              ///< after downsampling
  double rmse = 0.0;                                          ///< metres, over the final pairs
  int iterations = 0;
  bool converged = false;
  double seconds = 0.0;  ///< wall time of this registration, including the preprocessing it did
  TranslationConstraint constraint;
  Assessment assessment;

  [[nodiscard]] bool accepted() const { return assessment.verdict == Verdict::kAccepted; }
};

/// Scan-to-scan registration as a pipeline: preprocess the target once, then for each source scan
/// downsample, align coarse to fine, and judge the result.
class ScanRegistration {
 public:
  explicit ScanRegistration(RegistrationOptions options = {});

  /// Downsamples and indexes the scan the next sources are registered onto.
  void set_target(const PointCloud& target);
  /// Indexes a target that is already cropped and thinned (a local map), as it is. `normals`: estimates
  /// for its first points from an earlier target that began with the same points (take_normals()).
  void set_thinned_target(PointCloud target, LazyNormals::Estimates normals = {});
  /// The target's normals estimated so far, moved out (the target then has none until the next
  /// set_target).
  [[nodiscard]] LazyNormals::Estimates take_normals();
  /// Registers `source` onto the target, starting from `guess` (source -> target). Needs set_target.
  [[nodiscard]] RegistrationResult register_scan(const PointCloud& source, const Eigen::Isometry3d& guess);

  [[nodiscard]] const RegistrationOptions& options() const { return options_; }

 private:
  RegistrationOptions options_;
  std::unique_ptr<KdTree> target_;  // stable address: normals_ points into it
  std::unique_ptr<LazyNormals> normals_;
};

/// One-off registration of `source` onto `target`; `seconds` covers both scans' preprocessing.
[[nodiscard]] RegistrationResult register_scan(const PointCloud& source, const PointCloud& target,
                                               const Eigen::Isometry3d& guess,
                                               const RegistrationOptions& options = {});

}  // namespace strata

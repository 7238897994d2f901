#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/ann/growing_kdtree.hpp"
#include "core/points/point_cloud.hpp"
#include "core/registration/fault_check.hpp"
#include "core/registration/icp.hpp"
#include "core/registration/normals.hpp"

namespace strata {

/// One stage of the coarse-to-fine alignment: ICP runs to convergence at each stage's bound in turn, so a
/// guess that is off by more than the final (thesis) 0.25 m still finds its surfaces.
struct RegistrationStage {
  double max_correspondence_distance = 0.25;  ///< metres
  /// metres; the source is thinned to one point per voxel for this stage: the coarse stage only has to
  /// bring the guess within the fine bound, which fewer points do as well (docs/benchmarks.md, ICP).
  double source_voxel_size = 0.3;
  /// At most this many source points at this stage; 0: RegistrationOptions::max_source_points.
  std::size_t max_source_points = 0;
  double mse_change_threshold = 0.0;  ///< m^2; 0: not on the MSE (IcpOptions)
  double min_step_translation = 0.0;  ///< metres; with min_step_rotation, 0: not on the step (IcpOptions)
  double min_step_rotation = 0.0;     ///< radians
  int max_iterations = 100;
};

struct RegistrationOptions {
  /// Coarse to fine. Each stops when a step moves the source by less than its limits: point-to-point ICP
  /// creeps the last centimetres, and the fine stage has to be let run until the steps are tenths of a
  /// millimetre for the result not to depend on where it happened to stop. Measured on the real pairs in
  /// tests/bench/registration_bench.cpp.
  std::vector<RegistrationStage> stages = {
      {.max_correspondence_distance = 1.0,
       .source_voxel_size = 0.6,
       .min_step_translation = 5e-3,
       .min_step_rotation = 0.05 * 3.14159265358979323846 / 180.0},
      {.max_correspondence_distance = 0.25,
       .source_voxel_size = 0.3,
       .min_step_translation = 3e-4,
       .min_step_rotation = 0.003 * 3.14159265358979323846 / 180.0},
  };
  /// metres; 10 cm rather than 5 costs no accuracy on the real pairs and halves the target to index
  /// (docs/benchmarks.md, ICP).
  double target_voxel_size = 0.1;
  double min_range = 0.3;  ///< drop returns closer than this to the sensor (the robot itself)
  /// At most this many source points per stage (0: no limit): a scan that leaves more at a stage's voxel
  /// size is sampled down to it. A 32-beam lidar on a road keeps 10,000 points at 0.3 m, and ICP's time
  /// goes with them (docs/benchmarks.md, "Real captures").
  std::size_t max_source_points = 0;
  /// What the stages share (metric, rotation solver, kernel, minimum pairs); each stage sets the bound
  /// and the stop.
  IcpOptions icp;
  /// The degeneracy check's normals: at most this many pairs, spread evenly over the pairing (0: all); its
  /// eigenvalues are means, which a sample estimates as well at a quarter of the cost (docs/benchmarks.md).
  std::size_t max_constraint_pairs = 512;
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
  /// `viewpoints`: per target point, where the sensor was that saw it (or none): with the source's
  /// (set_source_viewpoint), pairs across a thin wall are told (IcpOptions::surface_sides).
  void set_thinned_target(PointCloud target, LazyNormals::Estimates normals = {},
                          std::vector<Eigen::Vector3d> viewpoints = {});
  /// The same for a target that grows at its end between changes of `layout` (LocalMap::layout(): its
  /// points keep their places until some go or all move): only the points beyond the last call's are
  /// indexed anew (GrowingKdTree), and the viewpoints beyond them copied.
  void follow_target(const PointCloud& target, std::uint64_t layout, LazyNormals::Estimates normals,
                     const std::vector<Eigen::Vector3d>& viewpoints);
  /// Where the next sources' sensor is, in their own frame.
  void set_source_viewpoint(const Eigen::Vector3d& viewpoint) { source_viewpoint_ = viewpoint; }
  /// The target's normals estimated so far, moved out (no registration until the next set_target or
  /// follow_target).
  [[nodiscard]] LazyNormals::Estimates take_normals();
  /// Registers `source` onto the target, starting from `guess` (source -> target). Needs set_target.
  [[nodiscard]] RegistrationResult register_scan(const PointCloud& source, const Eigen::Isometry3d& guess);
  /// The same, judged by `limits` instead of the options' (a guess less certain than usual).
  [[nodiscard]] RegistrationResult register_scan(const PointCloud& source, const Eigen::Isometry3d& guess,
                                                 const FaultLimits& limits);

  [[nodiscard]] const RegistrationOptions& options() const { return options_; }

 private:
  RegistrationOptions options_;
  std::unique_ptr<GrowingKdTree> target_;       // stable address: normals_ points into it
  std::optional<std::uint64_t> target_layout_;  // follow_target's, while the target is the one it follows
  std::unique_ptr<LazyNormals> normals_;
  std::vector<Eigen::Vector3d> viewpoints_;  // per target point, or none
  Eigen::Vector3d source_viewpoint_ = Eigen::Vector3d::Zero();
};

/// One-off registration of `source` onto `target`; `seconds` covers both scans' preprocessing.
[[nodiscard]] RegistrationResult register_scan(const PointCloud& source, const PointCloud& target,
                                               const Eigen::Isometry3d& guess,
                                               const RegistrationOptions& options = {});

}  // namespace strata

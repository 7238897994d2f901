#include "core/registration/register_scan.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <utility>

#include "core/points/voxel_downsample.hpp"
#include "core/registration/degeneracy.hpp"

namespace strata {
namespace {

/// Neighbours per normal estimate (LazyNormals' default).
constexpr std::size_t kNormalNeighbours = 20;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PointCloud preprocess(const PointCloud& scan, double min_range, double voxel_size) {
  return voxel_downsample(scan, voxel_size, min_range);
}

/// At most `budget` of the points (0: all), spread evenly over them. The thinned points come in scan
/// order, so the sample keeps their spread over the scan and their share of near and far surfaces;
/// larger voxels instead keep the far, sparse rings whole and thin the near surfaces, and the pairs fell
/// from 56 to 43 % of the points on the HDL-32E capture (docs/benchmarks.md, "Real captures").
PointCloud spread_sample(PointCloud points, std::size_t budget) {
  if (budget == 0 || points.size() <= budget)
    return points;
  for (std::size_t k = 0; k < budget; ++k)
    points[k] = points[k * points.size() / budget];  // k * n / budget >= k: never a point already moved
  points.resize(budget);
  return points;
}

/// The source thinned once per voxel size and point budget the stages ask for: the scan pass (cropping
/// included) at the finest size, the coarser sizes from that, which is a tenth of the points.
class SourceLevels {
 public:
  SourceLevels(const PointCloud& scan, const RegistrationOptions& options) {
    double finest = options.stages.front().source_voxel_size;
    for (const RegistrationStage& stage : options.stages)
      finest = std::min(finest, stage.source_voxel_size);
    const PointCloud thinned = preprocess(scan, options.min_range, finest);
    for (const RegistrationStage& stage : options.stages) {
      const Level level{stage.source_voxel_size, budget(stage, options)};
      if (find(level) != nullptr)
        continue;
      PointCloud points = level.voxel_size == finest ? thinned : voxel_downsample(thinned, level.voxel_size);
      levels_.emplace_back(level, spread_sample(std::move(points), level.budget));
    }
  }

  [[nodiscard]] const PointCloud& at(const RegistrationStage& stage,
                                     const RegistrationOptions& options) const {
    return *find({stage.source_voxel_size, budget(stage, options)});
  }

 private:
  struct Level {
    double voxel_size = 0.0;
    std::size_t budget = 0;
    bool operator==(const Level&) const = default;
  };

  static std::size_t budget(const RegistrationStage& stage, const RegistrationOptions& options) {
    return stage.max_source_points > 0 ? stage.max_source_points : options.max_source_points;
  }

  [[nodiscard]] const PointCloud* find(const Level& level) const {
    for (const auto& [known, points] : levels_) {
      if (known == level)
        return &points;
    }
    return nullptr;
  }

  std::vector<std::pair<Level, PointCloud>> levels_;
};

/// At most `count` of the pairs, spread evenly over them (all of them if `count` is 0 or enough).
std::vector<Correspondence> spread_sample(const std::vector<Correspondence>& pairs, std::size_t count) {
  if (count == 0 || pairs.size() <= count)
    return pairs;
  std::vector<Correspondence> sample;
  sample.reserve(count);
  for (std::size_t k = 0; k < count; ++k)
    sample.push_back(pairs[k * pairs.size() / count]);
  return sample;
}

}  // namespace

ScanRegistration::ScanRegistration(RegistrationOptions options) : options_(std::move(options)) {}

void ScanRegistration::set_target(const PointCloud& target) {
  set_thinned_target(preprocess(target, options_.min_range, options_.target_voxel_size));
}

void ScanRegistration::set_thinned_target(PointCloud target, LazyNormals::Estimates normals,
                                          std::vector<Eigen::Vector3d> viewpoints) {
  normals_.reset();
  viewpoints_ = std::move(viewpoints);
  target_ = std::make_unique<GrowingKdTree>(std::move(target));
  target_layout_.reset();
  normals_ = std::make_unique<LazyNormals>(*target_, kNormalNeighbours, std::move(normals));
}

void ScanRegistration::follow_target(const PointCloud& target, std::uint64_t layout,
                                     LazyNormals::Estimates normals,
                                     const std::vector<Eigen::Vector3d>& viewpoints) {
  normals_.reset();
  if (target_ && target_layout_ == layout && target.size() >= target_->size()) {
    const std::size_t known = target_->size();
    target_->append(std::span(target).subspan(known));
    if (viewpoints.size() == target.size() && viewpoints_.size() == known)
      viewpoints_.insert(viewpoints_.end(), viewpoints.begin() + static_cast<std::ptrdiff_t>(known),
                         viewpoints.end());
    else
      viewpoints_ = viewpoints;
  } else {
    target_ = std::make_unique<GrowingKdTree>(target);
    target_layout_ = layout;
    viewpoints_ = viewpoints;
  }
  normals_ = std::make_unique<LazyNormals>(*target_, kNormalNeighbours, std::move(normals));
}

LazyNormals::Estimates ScanRegistration::take_normals() {
  if (!normals_)
    return {};
  LazyNormals::Estimates estimates = normals_->take();
  normals_.reset();
  return estimates;
}

RegistrationResult ScanRegistration::register_scan(const PointCloud& source, const Eigen::Isometry3d& guess) {
  return register_scan(source, guess, options_.limits);
}

RegistrationResult ScanRegistration::register_scan(const PointCloud& source, const Eigen::Isometry3d& guess,
                                                   const FaultLimits& limits) {
  if (!target_ || !normals_)
    throw std::logic_error("ScanRegistration::register_scan called before set_target or after take_normals");
  if (options_.stages.empty())
    throw std::invalid_argument("RegistrationOptions::stages is empty");
  const auto start = std::chrono::steady_clock::now();
  const SourceLevels source_levels(source, options_);

  IcpResult icp;
  icp.transform = guess;
  const PointCloud* points = nullptr;
  const SurfaceSides sides{.target_viewpoints = &viewpoints_, .source_viewpoint = source_viewpoint_};
  const bool seen_from = viewpoints_.size() == target_->size();
  for (const RegistrationStage& stage : options_.stages) {
    IcpOptions icp_options = options_.icp;
    icp_options.max_correspondence_distance = stage.max_correspondence_distance;
    icp_options.mse_change_threshold = stage.mse_change_threshold;
    icp_options.min_step_translation = stage.min_step_translation;
    icp_options.min_step_rotation = stage.min_step_rotation;
    icp_options.max_iterations = stage.max_iterations;
    points = &source_levels.at(stage, options_);
    const int iterations_so_far = icp.iterations;
    icp = align(*points, *target_, normals_.get(), icp.transform, icp_options, seen_from ? &sides : nullptr);
    icp.iterations += iterations_so_far;
  }

  RegistrationResult result;
  result.refined = icp.transform;
  result.pairs = icp.pairs.size();
  result.source_points = points->size();
  result.target_points = target_->size();
  result.rmse = icp.rmse;
  result.iterations = icp.iterations;
  result.converged = icp.converged;
  result.constraint = translation_constraint(spread_sample(icp.pairs, options_.max_constraint_pairs),
                                             *normals_, target_->points());
  result.assessment = assess({.pairs = result.pairs,
                              .source_points = result.source_points,
                              .rmse = result.rmse,
                              .guess = guess,
                              .result = icp.transform,
                              .constraint = result.constraint},
                             limits);
  result.transform = result.accepted() ? icp.transform : guess;
  result.seconds = seconds_since(start);
  return result;
}

RegistrationResult register_scan(const PointCloud& source, const PointCloud& target,
                                 const Eigen::Isometry3d& guess, const RegistrationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ScanRegistration registration(options);
  registration.set_target(target);
  RegistrationResult result = registration.register_scan(source, guess);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace strata

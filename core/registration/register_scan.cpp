#include "core/registration/register_scan.hpp"

#include <chrono>
#include <limits>
#include <stdexcept>

#include "core/points/voxel_downsample.hpp"

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

}  // namespace

ScanRegistration::ScanRegistration(RegistrationOptions options) : options_(std::move(options)) {}

void ScanRegistration::set_target(const PointCloud& target) {
  set_thinned_target(preprocess(target, options_.min_range, options_.target_voxel_size));
}

void ScanRegistration::set_thinned_target(PointCloud target, LazyNormals::Estimates normals) {
  normals_.reset();
  target_ = std::make_unique<KdTree>(std::move(target));
  normals_ = std::make_unique<LazyNormals>(*target_, kNormalNeighbours, std::move(normals));
}

LazyNormals::Estimates ScanRegistration::take_normals() {
  if (!normals_)
    return {};
  LazyNormals::Estimates estimates = normals_->take();
  normals_.reset();
  target_.reset();
  return estimates;
}

RegistrationResult ScanRegistration::register_scan(const PointCloud& source, const Eigen::Isometry3d& guess) {
  if (!target_)
    throw std::logic_error("ScanRegistration::register_scan called before set_target");
  const auto start = std::chrono::steady_clock::now();
  const PointCloud points = preprocess(source, options_.min_range, options_.source_voxel_size);

  IcpResult icp;
  icp.transform = guess;
  const std::vector<double>& schedule = options_.correspondence_schedule;
  for (std::size_t k = 0; k < schedule.size(); ++k) {
    IcpOptions stage = options_.icp;
    stage.max_correspondence_distance = schedule[k];
    if (k + 1 == schedule.size())
      stage.mse_change_threshold = options_.fine_mse_change_threshold;
    const int iterations_so_far = icp.iterations;
    icp = align(points, *target_, normals_.get(), icp.transform, stage);
    icp.iterations += iterations_so_far;
  }

  RegistrationResult result;
  result.refined = icp.transform;
  result.pairs = icp.pairs.size();
  result.source_points = points.size();
  result.target_points = target_->size();
  result.rmse = icp.rmse;
  result.iterations = icp.iterations;
  result.converged = icp.converged;
  result.constraint = translation_constraint(icp.pairs, *normals_, target_->points());
  result.assessment = assess({.pairs = result.pairs,
                              .source_points = result.source_points,
                              .rmse = result.rmse,
                              .guess = guess,
                              .result = icp.transform,
                              .constraint = result.constraint},
                             options_.limits);
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

#include "drivers/sim/scanners/tilting_scanner.hpp"

#include <cmath>
#include <stdexcept>

#include "core/geometry/angles.hpp"

namespace strata::sim {

TiltingScanner::TiltingScanner(TiltingScannerConfig config, std::uint64_t seed)
    : config_(config), rng_(seed ^ 0x7111'7111ULL) {
  if (!(config_.slice_step_deg > 0.0) || !(config_.rotation_step_deg > 0.0) ||
      !(config_.slices_per_second > 0.0)) {
    throw std::invalid_argument("tilting scanner steps and rate must be positive");
  }
  slices_ = static_cast<int>(std::round(config_.rotation_deg / config_.rotation_step_deg));
  beams_per_slice_ = static_cast<int>(std::round(config_.slice_fov_deg / config_.slice_step_deg)) + 1;
}

double TiltingScanner::duration() const {
  return slices_ / config_.slices_per_second;
}

std::size_t TiltingScanner::rays_per_scan() const {
  return static_cast<std::size_t>(slices_) * static_cast<std::size_t>(beams_per_slice_);
}

ScanEvent TiltingScanner::empty_event() const {
  ScanEvent event;
  event.sensor = "tilting-laser";
  event.duration = duration();
  event.sensor_to_base.translation() = config_.mount;
  event.max_range = config_.beam.no_return == NoReturn::kMaxRange ? config_.beam.max_range : 0.0;
  event.points.reserve(rays_per_scan());
  return event;
}

void TiltingScanner::fire_slice(const World& world, const Eigen::Isometry3d& sensor, int slice,
                                ScanEvent& event) {
  const double deg = kPi / 180.0;
  const double azimuth = slice * config_.rotation_step_deg * deg;
  const double ca = std::cos(azimuth);
  const double sa = std::sin(azimuth);
  const double lowest = -config_.slice_fov_deg / 2 * deg;
  for (int b = 0; b < beams_per_slice_; ++b) {
    const double elevation = lowest + b * config_.slice_step_deg * deg;
    const Eigen::Vector3d direction(std::cos(elevation) * ca, std::cos(elevation) * sa, std::sin(elevation));
    if (auto point = config_.beam.measure(world, sensor, direction, rng_))
      event.points.push_back(*point);
  }
  event.rays += static_cast<std::size_t>(beams_per_slice_);
}

ScanEvent TiltingScanner::scan(const World& world, const Eigen::Isometry3d& base_in_world) {
  ScanEvent event = empty_event();
  const Eigen::Isometry3d sensor = base_in_world * event.sensor_to_base;
  for (int s = 0; s < slices_; ++s)
    fire_slice(world, sensor, s, event);
  return event;
}

void TiltingScanner::begin(double t) {
  started_ = t;
  next_slice_ = 0;
  current_ = empty_event();
}

std::optional<ScanEvent> TiltingScanner::advance(const World& world, const Eigen::Isometry3d& base_in_world,
                                                 double /*t0*/, double t1) {
  if (next_slice_ < 0)
    return std::nullopt;
  const Eigen::Isometry3d sensor = base_in_world * current_.sensor_to_base;
  // Slice s fires at started_ + s / rate.
  while (next_slice_ < slices_ && started_ + next_slice_ / config_.slices_per_second < t1) {
    fire_slice(world, sensor, next_slice_++, current_);
  }
  if (next_slice_ < slices_)
    return std::nullopt;
  next_slice_ = -1;
  current_.stamp = t1;
  return std::move(current_);
}

}  // namespace strata::sim

#include "drivers/sim/scanners/spinning_lidar.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/geometry/angles.hpp"

namespace strata::sim {

SpinningLidar::SpinningLidar(SpinningLidarConfig config, std::uint64_t seed)
    : config_(config), rng_(seed ^ 0x1d4a'1d4aULL) {
  if (config_.beams < 1 || !(config_.azimuth_step_deg > 0.0) || !(config_.rotation_hz > 0.0)) {
    throw std::invalid_argument("lidar needs beams >= 1 and positive azimuth step and rotation rate");
  }
  columns_ = static_cast<int>(std::round(360.0 / config_.azimuth_step_deg));
  const double deg = kPi / 180.0;
  for (int b = 0; b < config_.beams; ++b) {
    const double fraction = config_.beams == 1 ? 0.5 : static_cast<double>(b) / (config_.beams - 1);
    const double elevation =
        (config_.elevation_min_deg + fraction * (config_.elevation_max_deg - config_.elevation_min_deg)) *
        deg;
    fan_.emplace_back(std::cos(elevation), 0.0, std::sin(elevation));
  }
  current_.sensor = "vlp16";
  current_.sensor_to_base.translation() = config_.mount;
}

std::size_t SpinningLidar::rays_per_revolution() const {
  return static_cast<std::size_t>(columns_) * fan_.size();
}

void SpinningLidar::fire(const World& world, const Eigen::Isometry3d& sensor, int column, float time) {
  const double azimuth = column * config_.azimuth_step_deg * kPi / 180.0;
  const Eigen::AngleAxisd turn(azimuth, Eigen::Vector3d::UnitZ());
  for (const Eigen::Vector3d& beam : fan_) {
    if (auto point = config_.beam.measure(world, sensor, turn * beam, rng_)) {
      current_.points.push_back(*point);
      current_.point_times.push_back(time);
    }
  }
  current_.rays += fan_.size();
}

std::optional<ScanEvent> SpinningLidar::advance(const World& world, const Eigen::Isometry3d& base_in_world,
                                                double t0, double t1) {
  const double period = 1.0 / config_.rotation_hz;
  const double firing_interval = period / columns_;
  const Eigen::Isometry3d sensor = base_in_world * current_.sensor_to_base;
  std::optional<ScanEvent> completed;
  // Start with the first whole revolution after the lidar is switched on.
  if (next_column_ < 0)
    next_column_ = static_cast<long long>(std::ceil(t0 / period)) * columns_;
  // Firing k happens at k * firing_interval; fire those before t1.
  while (static_cast<double>(next_column_) * firing_interval < t1) {
    // When this column fires, relative to the end of its revolution (the scan's stamp).
    const int column = static_cast<int>(next_column_ % columns_);
    fire(world, sensor, column, static_cast<float>(static_cast<double>(column - columns_) * firing_interval));
    ++next_column_;
    if (next_column_ % columns_ == 0) {
      current_.duration = period;
      current_.stamp = static_cast<double>(next_column_) * firing_interval;
      completed = std::move(current_);
      current_ = ScanEvent{};
      current_.sensor = completed->sensor;
      current_.sensor_to_base = completed->sensor_to_base;
      current_.points.reserve(completed->points.size());
      current_.point_times.reserve(completed->points.size());
    }
  }
  return completed;
}

}  // namespace strata::sim

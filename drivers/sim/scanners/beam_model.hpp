#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <random>

#include "drivers/sim/world/world.hpp"

namespace strata::sim {

/// What a laser reports when a beam finds no surface within its range.
enum class NoReturn {
  kDrop,      ///< nothing (Velodyne, Ouster: zero range, dropped by the driver)
  kMaxRange,  ///< a reading at maximum range (SICK LMS200: the 8.183 m code)
};

/// How a simulated laser beam measures: range limits, Gaussian range noise, no-return behaviour.
struct BeamModel {
  double min_range = 0.1;      ///< m; closer returns are discarded, as by the sensor
  double max_range = 8.1;      ///< m
  double range_stddev = 0.01;  ///< m, Gaussian noise on every range
  NoReturn no_return = NoReturn::kDrop;

  /// Measures one beam from `sensor` (sensor frame -> world) along `direction` (unit, sensor frame).
  /// Returns the point in the sensor frame, or nothing when the sensor reports nothing.
  template <class Rng>
  std::optional<Eigen::Vector3f> measure(const World& world, const Eigen::Isometry3d& sensor,
                                         const Eigen::Vector3d& direction, Rng& rng) const {
    const Ray ray{sensor.translation(), sensor.linear() * direction};
    const auto hit = world.cast(ray, max_range);
    double range = 0.0;
    if (hit) {
      std::normal_distribution<double> noise(0.0, range_stddev);
      range = hit->distance + (range_stddev > 0.0 ? noise(rng) : 0.0);
      if (range < min_range)
        return std::nullopt;
      if (range > max_range)
        range = max_range;
    } else if (no_return == NoReturn::kMaxRange) {
      range = max_range;
    } else {
      return std::nullopt;
    }
    return (direction * range).cast<float>();
  }
};

}  // namespace strata::sim

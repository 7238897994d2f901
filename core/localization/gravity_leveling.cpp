#include "core/localization/gravity_leveling.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/geometry/pose.hpp"

namespace strata {
namespace {

/// The turn, as a rotation vector in the map frame, that takes the reading's up (carried into the map by
/// `pose`) onto the map's up.
Eigen::Vector3d tilt_error(const Eigen::Isometry3d& pose, const Eigen::Vector3d& up_in_base) {
  const Eigen::Vector3d measured_up = pose.linear() * up_in_base;
  const Eigen::Vector3d axis = measured_up.cross(Eigen::Vector3d::UnitZ());
  const double sine = axis.norm();
  if (sine == 0.0)
    return Eigen::Vector3d::Zero();
  return axis / sine * std::atan2(sine, measured_up.z());
}

/// `turn` (map frame), less what it would turn `orientation`'s heading. Gravity tells tilt, not heading,
/// but a turn about a level axis moves a tilted pose's heading at second order: on the campus hill a
/// guess tilted 3-5 degrees toward its reading took 0.1-0.3 degrees of heading with it, the same way on
/// every run, and on open ground nothing turned it back (docs/benchmarks.md, "Tilt corrections keep the
/// heading").
Eigen::Matrix3d keeping_heading(const Eigen::Matrix3d& turn, const Eigen::Matrix3d& orientation) {
  const double moved = std::remainder(
      heading_of(Eigen::Isometry3d(turn * orientation)) - heading_of(Eigen::Isometry3d(orientation)),
      2.0 * std::numbers::pi);
  return Eigen::AngleAxisd(-moved, Eigen::Vector3d::UnitZ()).toRotationMatrix() * turn;
}

}  // namespace

bool GravityLeveling::usable(const GravityReading& gravity) {
  return gravity.up_in_base.allFinite() && std::abs(gravity.up_in_base.norm() - 1.0) < 0.01 &&
         std::isfinite(gravity.sigma) && gravity.sigma > 0.0;
}

GravityLeveling::GravityLeveling(GravityLevelingOptions options, bool start_given)
    : options_(options),
      variance_(
          std::pow(start_given ? options.given_start_tilt_sigma : options.unknown_start_tilt_sigma, 2)) {}

GravityReading GravityLeveling::without_mounting(const GravityReading& gravity,
                                                 const Eigen::Vector3d& mounting) {
  if (!usable(gravity))
    return gravity;
  GravityReading out = gravity;
  out.up_in_base =
      (rotation_from_vector(mounting).transpose() * gravity.up_in_base.normalized()).normalized();
  return out;
}

GravityReading GravityLeveling::corrected(const GravityReading& gravity) const {
  return without_mounting(gravity, bias_);
}

Eigen::Matrix3d GravityLeveling::level(const Eigen::Isometry3d& pose, const GravityReading& gravity) {
  if (!usable(gravity))
    return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d error = tilt_error(pose, corrected(gravity).up_in_base);
  // What is left of the error in the base frame is, on average, the mounting error not yet learnt (a
  // reading tilted by b about the base's axes asks for a turn of about -b).
  Eigen::Vector3d in_base = pose.linear().transpose() * error;
  in_base.z() = 0.0;
  const double heading = heading_of(pose);
  const double turned =
      last_heading_ ? std::abs(std::remainder(heading - *last_heading_, 2.0 * std::numbers::pi)) : 0.0;
  last_heading_ = heading;
  bias_ -= std::min(1.0, options_.bias_rate_per_radian * turned) * in_base;
  variance_ += options_.drift_per_scan * options_.drift_per_scan;
  const double gain = variance_ / (variance_ + gravity.sigma * gravity.sigma);
  variance_ *= 1.0 - gain;
  return keeping_heading(rotation_from_vector(gain * error), pose.linear());
}

Eigen::Matrix3d GravityLeveling::align(const Eigen::Isometry3d& pose, const GravityReading& gravity,
                                       std::optional<double> moved) const {
  if (!usable(gravity))
    return Eigen::Matrix3d::Identity();
  // Nothing known of the motion (the first scan): as sure of the tilt as the filter is. A start at a
  // given pose keeps its tilt against one reading taken while driving; an unknown one takes it.
  double gain = variance_ / (variance_ + gravity.sigma * gravity.sigma);
  if (moved) {
    const double change = options_.tilt_change_per_metre * *moved;
    gain = change * change / (change * change + gravity.sigma * gravity.sigma);
  }
  return keeping_heading(rotation_from_vector(gain * tilt_error(pose, corrected(gravity).up_in_base)),
                         pose.linear());
}

}  // namespace strata

#pragma once

#include <span>

#include "core/geometry/pose.hpp"
#include "core/points/point_cloud.hpp"

namespace strata {

/// Undoes the base's motion while a spinning lidar turned: each point, measured at `times[i]` seconds
/// relative to the scan's stamp (<= 0, the revolution's end) in the frame the base had then, is moved
/// into the base's frame at the stamp, for a base moving at `velocity` (per second, in its own frame:
/// forward, left, turn rate) the whole revolution long. At 1 m/s a 10 Hz revolution is smeared by 10 cm,
/// turning at 0.5 rad/s by 0.5 m at 10 m range (docs/benchmarks.md). Planar, as the motion models are.
/// `times` empty: the points stay as they are (the sensor said nothing of when it measured them).
void deskew(PointCloud& points, std::span<const float> times, const Pose2& velocity);

/// Where a base moving at `velocity` (per second, its own frame) is after `seconds` (negative: before),
/// relative to where it is now: the planar exponential of the constant motion, exact on arcs.
[[nodiscard]] Pose2 pose_after(const Pose2& velocity, double seconds);

}  // namespace strata

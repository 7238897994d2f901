#pragma once

#include "core/points/point_cloud.hpp"
#include "drivers/scan_event.hpp"

namespace strata::pipeline {

/// Step 1 of the pipeline (docs/architecture.md 3): the scan's points in the robot's base frame, without
/// invalid (NaN, infinite) points, returns closer than `min_range` to the sensor (the robot itself), and
/// the sensor's max-range "no return" readings.
[[nodiscard]] PointCloud points_in_base(const ScanEvent& scan, double min_range = 0.3);

}  // namespace strata::pipeline

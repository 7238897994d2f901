#pragma once

#include <vector>

#include "core/points/point_cloud.hpp"
#include "core/points/scan_cleaning.hpp"
#include "drivers/scan_event.hpp"

namespace strata::pipeline {

/// Step 1 of the pipeline (docs/architecture.md 3): the scan cleaned (clean_scan: no invalid point, none
/// closer than `min_range` to the sensor, no max-range "no return") in the robot's base frame. `times`,
/// when given, gets the kept points' times (ScanEvent::point_times; empty when the scan has none).
[[nodiscard]] PointCloud points_in_base(const ScanEvent& scan, double min_range = 0.3,
                                        std::vector<float>* times = nullptr);

/// A scan after step 1, as it travels on from the localizer to the mapping worker: preprocessed once.
struct PreprocessedScan {
  ScanEvent event;    ///< as the driver took it, without its raw points (`points` replaces them)
  PointCloud points;  ///< points_in_base(event)
  /// When each of `points` was measured, relative to the stamp (empty: unknown). The localizer deskews
  /// `points` with them before anything else uses the scan.
  std::vector<float> times;
};

/// Step 1 for a scan the pipeline takes over: its points in the base frame, the raw ones released.
[[nodiscard]] PreprocessedScan preprocess(ScanEvent scan, double min_range = 0.3);

}  // namespace strata::pipeline

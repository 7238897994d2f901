#include "server/pipeline/scan_preprocessing.hpp"

#include <limits>

namespace strata::pipeline {

PointCloud points_in_base(const ScanEvent& scan, double min_range) {
  // Max-range readings sit exactly at the limit; noise can push real returns just under it, so keep a
  // margin of a centimetre.
  const double max_range =
      scan.max_range > 0.0 ? scan.max_range - 0.01 : std::numeric_limits<double>::infinity();
  PointCloud points;
  points.reserve(scan.points.size());
  for (const Eigen::Vector3f& p : scan.points) {
    if (!p.allFinite())
      continue;
    const double range = static_cast<double>(p.norm());
    if (range < min_range || range > max_range)
      continue;
    points.push_back(scan.sensor_to_base * p.cast<double>());
  }
  return points;
}

PreprocessedScan preprocess(ScanEvent scan, double min_range) {
  PreprocessedScan preprocessed;
  preprocessed.points = points_in_base(scan, min_range);
  scan.points = {};  // the raw points are done with: free them before the scan waits in a queue
  preprocessed.event = std::move(scan);
  return preprocessed;
}

}  // namespace strata::pipeline

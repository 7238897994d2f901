#include "server/pipeline/scan_preprocessing.hpp"

#include <limits>

namespace strata::pipeline {

PointCloud points_in_base(const ScanEvent& scan, double min_range, std::vector<float>* times) {
  // Max-range readings sit exactly at the limit; noise can push real returns just under it, so keep a
  // margin of a centimetre.
  const double max_range =
      scan.max_range > 0.0 ? scan.max_range - 0.01 : std::numeric_limits<double>::infinity();
  const bool timed = times != nullptr && scan.point_times.size() == scan.points.size();
  if (times != nullptr) {
    times->clear();
    if (timed)
      times->reserve(scan.points.size());
  }
  PointCloud points;
  points.reserve(scan.points.size());
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const Eigen::Vector3f& p = scan.points[i];
    if (!p.allFinite())
      continue;
    const double range = static_cast<double>(p.norm());
    if (range < min_range || range > max_range)
      continue;
    points.push_back(scan.sensor_to_base * p.cast<double>());
    if (timed)
      times->push_back(scan.point_times[i]);
  }
  return points;
}

PreprocessedScan preprocess(ScanEvent scan, double min_range) {
  PreprocessedScan preprocessed;
  preprocessed.points = points_in_base(scan, min_range, &preprocessed.times);
  // The raw points are done with: free them before the scan waits in a queue.
  scan.points = {};
  scan.point_times = {};
  preprocessed.event = std::move(scan);
  return preprocessed;
}

}  // namespace strata::pipeline

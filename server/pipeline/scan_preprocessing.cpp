#include "server/pipeline/scan_preprocessing.hpp"

namespace strata::pipeline {

PointCloud points_in_base(const ScanEvent& scan, double min_range, std::vector<float>* times) {
  return clean_scan(scan.points, scan.sensor_to_base,
                    {.min_range = min_range, .no_return_range = scan.max_range}, scan.point_times, times);
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

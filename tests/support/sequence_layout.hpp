#pragma once

#include <filesystem>

namespace strata::test {

/// A directory `strata serve --replay` plays as a lidar alone with a reference: DIR itself when it has a
/// scans.csv (file, stamp, truth_x ... truth_yaw), else a scans.csv written into `scratch` from a layout of
/// the shared data (../shared/data/sequences/README.txt):
/// - BALM: full<k>.pcd with alidarPose.csv (4 lines a scan: the rows of T_world_scan, then "0,0,0,stamp");
/// - keyframes: Scans/<k>.pcd with optimized_poses.txt (KITTI 3x4 rows of T_world_keyframe) and times.txt.
/// The point files stay where they are (absolute paths). `every` > 1 keeps every n-th scan only (from the
/// first): scans dropped, and turns between scans n times as sharp. Throws std::runtime_error for anything
/// else.
[[nodiscard]] std::filesystem::path scan_list_for(const std::filesystem::path& dir,
                                                  const std::filesystem::path& scratch,
                                                  std::size_t every = 1);

}  // namespace strata::test

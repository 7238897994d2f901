#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <filesystem>
#include <istream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/gravity.hpp"
#include "core/geometry/pose.hpp"
#include "core/geometry/standing_gyro.hpp"
#include "drivers/scan_event.hpp"

namespace strata::replay {

/// A directory that is not a dataset Strata can replay, or one with something wrong in it: says which
/// file and what.
class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The layouts a replay recognises (README.md, "Replay and recording").
enum class DatasetLayout {
  kRecording,  ///< Strata's own: recording.json, scans.csv, scans/NNNNNN.pcd, odometry.csv (strata serve
               ///< --record)
  kScanList,   ///< scans.csv listing point files (PCD, PLY, 3DTK, xyz) with stamps and poses, no
               ///< recording.json
  kThreeDtk,   ///< 3DTK / slam6D: scanNNN.3d + scanNNN.pose, optional scanNNN.frames as reference poses
  kKitti,      ///< KITTI odometry: velodyne/NNNNNN.bin + poses.txt (reference), optional times.txt, calib.txt
  kMcap,       ///< Strata's recording as an MCAP file of ROS 2 messages (strata serve --record-mcap)
};
[[nodiscard]] std::string to_string(DatasetLayout layout);

/// Where the points of scans are when they are not in files of their own (an MCAP recording's /scan
/// messages): read on the replay's thread.
class ScanStore {
 public:
  virtual ~ScanStore() = default;
  /// The index-th scan's points in its sensor frame and, when `times` is given, their times (s from the
  /// stamp; empty where not recorded). Throws DatasetError.
  [[nodiscard]] virtual std::vector<Eigen::Vector3f> points(std::size_t index, std::vector<float>* times) = 0;
};

/// One scan of a dataset; its points are read only when it is played (load_points).
struct DatasetScan {
  std::filesystem::path file;     ///< the point file
  double stamp = 0.0;             ///< seconds, the dataset's clock
  std::optional<Pose3> odometry;  ///< the dataset's odometry of the base at `stamp`
  std::optional<Pose3>
      reference;  ///< a reference pose of the base (ground truth, or an offline registration)
  Eigen::Isometry3d sensor_to_base = Eigen::Isometry3d::Identity();
  /// False where the dataset does not say where the sensor sits (a scan list without mount columns): the
  /// replay then estimates it from the ground (SensorMount).
  bool mount_known = true;
  std::string sensor = "replay";
  double duration = 0.0;
  std::size_t rays = 0;                       ///< 0: as many as points
  double max_range = 0.0;                     ///< readings at this range mean "no return"; 0: none
  std::optional<GravityReading> gravity;      ///< the base IMU's reading with the scan, where there is one
  std::optional<StandingGyro> standing_gyro;  ///< what its gyro read standing before the scan, where it did
  /// The point file's "time" field is seconds from `stamp` (Strata's recordings); other files' times have
  /// references of their own and are not used.
  bool times_from_stamp = false;
  /// Set where the points are in a store (`store_index` there) rather than in `file`.
  std::shared_ptr<ScanStore> store;
  std::size_t store_index = 0;
};

/// An odometry sample between scans (a recording has the full stream; other layouts have none).
struct DatasetOdometry {
  double stamp = 0.0;
  Pose3 odometry;
  std::optional<Pose3> reference;
};

struct Dataset {
  DatasetLayout layout = DatasetLayout::kRecording;
  std::filesystem::path directory;
  std::vector<DatasetScan> scans;         ///< in time order
  std::vector<DatasetOdometry> odometry;  ///< in time order; may be empty
  /// Where the odometry frame starts in the map frame, when the dataset says (a recording does).
  std::optional<Eigen::Isometry3d> initial_map_from_odom;
  std::string description;  ///< for the log, e.g. "3DTK, 3 scans, reference poses from reference_slam6d_2009"
};

/// Recognises the layout of `directory` (or an MCAP recording, a file ending in .mcap) and reads its index:
/// every list and pose file is read and checked (counts match, numbers are numbers, the point files exist),
/// the point files themselves are not. Throws DatasetError naming what is missing or wrong.
[[nodiscard]] Dataset open_dataset(const std::filesystem::path& directory);

/// The odometry.csv rows in `csv` (header first); `source` names it in errors. Throws DatasetError.
[[nodiscard]] std::vector<DatasetOdometry> parse_odometry_stream(std::istream& csv,
                                                                 const std::string& source);
/// recording.json's metadata: the format's name and version are checked (`format`, `version`), the initial
/// pose read into `dataset`, the description made. `source` names it in errors. Throws DatasetError.
void read_recording_metadata(const std::string& text, const std::string& source, std::string_view format,
                             int version, Dataset& dataset);

/// The points of one scan, in its sensor frame, as float (what a ScanEvent carries). `times`, when given,
/// gets when each was measured, seconds from the stamp, where the dataset says so (a recording of a lidar;
/// empty otherwise). Throws DatasetError.
[[nodiscard]] std::vector<Eigen::Vector3f> load_points(const DatasetScan& scan,
                                                       std::vector<float>* times = nullptr);

}  // namespace strata::replay

#include "server/pipeline/imu_calibration_store.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "core/files/atomic_file.hpp"

namespace strata::pipeline {
namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;

ImuCalibrationStatus status_of(ImuCalibrationStatus::Kept kept, const ImuCalibration& calibration) {
  return {.kept = kept,
          .imu = calibration.imu,
          .mounting_deg = calibration.mounting * kDegrees,
          .loops = calibration.loops};
}

}  // namespace

ImuCalibrationStore::ImuCalibrationStore(std::filesystem::path file, std::string imu)
    : file_(std::move(file)) {
  status_.kept = ImuCalibrationStatus::Kept::kNone;
  status_.imu = std::move(imu);
}

std::optional<ImuCalibration> ImuCalibrationStore::load() {
  std::lock_guard lock(mutex_);
  if (status_.kept == ImuCalibrationStatus::Kept::kOff)
    return std::nullopt;
  std::error_code error;
  if (!std::filesystem::exists(file_, error)) {
    spdlog::info("IMU calibration: none kept in {} yet; this run learns it", file_.string());
    return std::nullopt;
  }
  try {
    std::ifstream in(file_, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in)
      throw std::runtime_error("cannot be read");
    ImuCalibration calibration = parse_imu_calibration(text.str());
    if (calibration.imu != status_.imu) {
      spdlog::warn(
          "IMU calibration: {} is of {}, not of this robot's {}: not used (replaced at the first "
          "loop closure)",
          file_.string(), calibration.imu, status_.imu);
      return std::nullopt;
    }
    status_ = status_of(ImuCalibrationStatus::Kept::kLoaded, calibration);
    spdlog::info(
        "IMU calibration: starting from {} ({}: mounted {:.3f} degrees rolled, {:.3f} pitched, "
        "from {} loop closures)",
        file_.string(), calibration.imu, status_.mounting_deg->x(), status_.mounting_deg->y(),
        calibration.loops);
    return calibration;
  } catch (const std::exception& failure) {
    spdlog::warn("IMU calibration: {} is not used: {}", file_.string(), failure.what());
    return std::nullopt;
  }
}

void ImuCalibrationStore::update(const PoseGraphStatus& graph) {
  std::lock_guard lock(mutex_);
  if (status_.kept == ImuCalibrationStatus::Kept::kOff || graph.loops == 0 || graph.loops <= saved_loops_)
    return;
  const ImuCalibration calibration{.imu = status_.imu,
                                   .mounting = graph.gravity_mounting.head<2>(),
                                   .loops = graph.loops,
                                   .keyframes = graph.keyframes};
  if (!calibration.mounting.allFinite())
    return;
  try {
    std::filesystem::create_directories(file_.parent_path());
    write_file_atomically(file_, format_imu_calibration(calibration), Durability::kOnDisk);
    if (saved_loops_ == 0) {  // the first of this run's saves; the next ones only refine it
      spdlog::info(
          "IMU calibration: kept in {} for the next run ({} loop closures: mounted {:.3f} degrees "
          "rolled, {:.3f} pitched)",
          file_.string(), graph.loops, calibration.mounting.x() * kDegrees,
          calibration.mounting.y() * kDegrees);
    }
    saved_loops_ = graph.loops;
    status_ = status_of(ImuCalibrationStatus::Kept::kSaved, calibration);
  } catch (const std::exception& failure) {
    spdlog::error("IMU calibration: cannot keep it in {}: {}", file_.string(), failure.what());
  }
}

ImuCalibrationStatus ImuCalibrationStore::imu_calibration() const {
  std::lock_guard lock(mutex_);
  return status_;
}

CommandResult ImuCalibrationStore::clear_imu_calibration() {
  std::lock_guard lock(mutex_);
  if (status_.kept == ImuCalibrationStatus::Kept::kOff) {
    return CommandResult::failure(ErrorCode::kUnavailable,
                                  "no IMU calibration is kept: the robot has no IMU, or the server runs "
                                  "with --no-imu-calibration");
  }
  std::error_code error;
  const bool removed = std::filesystem::remove(file_, error);
  if (error)
    return CommandResult::failure(ErrorCode::kIoError,
                                  "cannot remove " + file_.filename().string() + ": " + error.message());
  status_ = ImuCalibrationStatus{.kept = ImuCalibrationStatus::Kept::kNone, .imu = status_.imu};
  // This run's estimate is kept again at its next loop closure, not at once: the operator cleared it.
  CommandResult result = CommandResult::success();
  result.message = removed ? "the IMU calibration is forgotten: the next run starts without one, unless "
                             "this run keeps its own at a later loop closure"
                           : "no IMU calibration was kept";
  spdlog::info("IMU calibration: {} ({})", result.message, file_.string());
  return result;
}

}  // namespace strata::pipeline

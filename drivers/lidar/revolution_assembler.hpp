#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "drivers/lidar/decoded_packet.hpp"

namespace strata::lidar {

/// The returns of one turn of the sensor.
struct Revolution {
  std::vector<LidarPoint> points;
  double start = 0.0;  ///< s, first column's firing
  double end = 0.0;    ///< s, last column's firing
  std::size_t rays = 0;
  std::size_t columns = 0;
  /// Began and ended at the cut (phase wrap) with no gap wider than the assembler's limit in between:
  /// a full 360 deg. The capture's (or stream's) first and last revolutions are partial.
  bool complete = false;
};

/// Cuts a stream of decoded columns into revolutions where the phase wraps (Velodyne azimuth through 0,
/// Ouster measurement id back to 0, i.e. a new frame id).
class RevolutionAssembler {
 public:
  /// A phase jump larger than `max_gap` (fraction of a turn) between consecutive columns marks the
  /// revolution incomplete (dropped packets). The default is a little over one lost VLP-16 packet.
  explicit RevolutionAssembler(double max_gap = 0.02) : max_gap_(max_gap) {}

  /// Adds one packet's columns; appends the revolutions they close to `done`.
  void add(const DecodedPacket& packet, std::vector<Revolution>& done);
  /// The revolution in progress (partial), if it has columns; the assembler starts afresh.
  [[nodiscard]] std::optional<Revolution> flush();

 private:
  Revolution current_;
  bool current_started_at_cut_ = false;
  bool has_previous_ = false;
  float previous_phase_ = 0.0f;
  double largest_gap_ = 0.0;
  double max_gap_;
  std::size_t last_size_ = 0;  ///< returns of the last closed revolution
};

}  // namespace strata::lidar

#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace strata::lidar {

/// One return, as a decoder produces it.
struct LidarPoint {
  Eigen::Vector3f position;  ///< m, sensor frame: x forward, y left, z up (ROS convention)
  float intensity = 0.0f;  ///< the sensor's own scale (Velodyne 0-255 calibrated reflectivity, Ouster signal)
  double time = 0.0;       ///< s, when this laser fired (same clock as the packet stamps)
  std::uint16_t ring = 0;  ///< 0 = lowest beam, counting up by elevation
};

/// One firing column: all lasers fired at (nearly) one azimuth. Columns let the revolution assembler cut
/// scans and count rays without looking at every point.
struct LidarColumn {
  double time = 0.0;              ///< s, first firing of the column
  float phase = 0.0f;             ///< where in the revolution, [0, 1); wraps to 0 at the cut
  std::uint32_t first_point = 0;  ///< index into DecodedPacket::points
  std::uint32_t point_count = 0;  ///< returns of this column (zero-range "no return" beams are left out)
  std::uint16_t rays = 0;         ///< beams fired, returns or not
};

/// What a decoder made of one UDP payload. Reused from packet to packet to avoid allocations.
struct DecodedPacket {
  std::vector<LidarColumn> columns;
  std::vector<LidarPoint> points;
  void clear() {
    columns.clear();
    points.clear();
  }
};

/// Why payloads were not (fully) decoded. A sensor network carries other traffic (Velodyne position
/// packets, Ouster IMU packets, anything broadcast), and a capture can be cut: all of it is counted,
/// never trusted.
struct DecodeStats {
  std::size_t packets = 0;           ///< payloads decoded (at least one valid block)
  std::size_t wrong_size = 0;        ///< payloads skipped: not the data-packet size of this sensor
  std::size_t no_valid_block = 0;    ///< payloads skipped: right size, but no block had a valid flag/status
  std::size_t invalid_blocks = 0;    ///< blocks skipped inside otherwise decoded packets
  std::size_t unsupported_mode = 0;  ///< payloads skipped: a return mode this decoder does not handle
  std::size_t model_mismatch = 0;    ///< decoded packets whose product byte names another model
  std::size_t returns = 0;           ///< points produced
  std::size_t rays = 0;              ///< beams fired
  [[nodiscard]] std::size_t skipped() const { return wrong_size + no_valid_block + unsupported_mode; }
};

}  // namespace strata::lidar

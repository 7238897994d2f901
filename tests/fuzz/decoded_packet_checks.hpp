#pragma once

// What every lidar decoder promises about what it appends, checked by the packet and calibration targets:
// the pipeline takes these points as they are (no later filter drops a non-finite one), and the revolution
// assembler indexes the points through the columns.
#include <cmath>
#include <cstddef>

#include "drivers/lidar/decoded_packet.hpp"

namespace strata::fuzz {

/// Traps unless the points and columns from `points_before` / `columns_before` on are consistent: every
/// point finite with a ring below `rings`, every column's points inside the packet and in order, every
/// phase in [0, 1), and no column with more returns than rays.
inline void check_decoded(const lidar::DecodedPacket& packet, std::size_t points_before,
                          std::size_t columns_before, std::size_t rings) {
  for (std::size_t i = points_before; i < packet.points.size(); ++i) {
    const lidar::LidarPoint& point = packet.points[i];
    if (!point.position.allFinite() || !std::isfinite(point.intensity) || !std::isfinite(point.time) ||
        point.ring >= rings)
      __builtin_trap();
  }
  std::size_t next_point = points_before;
  for (std::size_t c = columns_before; c < packet.columns.size(); ++c) {
    const lidar::LidarColumn& column = packet.columns[c];
    if (column.first_point != next_point || column.point_count > column.rays ||
        column.first_point + column.point_count > packet.points.size() || !(column.phase >= 0.0f) ||
        !(column.phase < 1.0f) || !std::isfinite(column.time))
      __builtin_trap();
    next_point += column.point_count;
  }
  if (next_point != packet.points.size())
    __builtin_trap();  // every point belongs to a column
}

}  // namespace strata::fuzz

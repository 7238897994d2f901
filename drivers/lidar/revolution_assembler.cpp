#include "drivers/lidar/revolution_assembler.hpp"

#include <algorithm>

namespace strata::lidar {

void RevolutionAssembler::add(const DecodedPacket& packet, std::vector<Revolution>& done) {
  for (const LidarColumn& column : packet.columns) {
    if (has_previous_) {
      double step = static_cast<double>(column.phase) - static_cast<double>(previous_phase_);
      // Phases only grow within a turn; a drop of more than half a turn is the wrap. Smaller drops
      // (reordered packets) are not cuts.
      const bool wrapped = step < -0.5;
      if (wrapped)
        step += 1.0;
      largest_gap_ = std::max(largest_gap_, step);
      if (wrapped && current_.columns > 0) {
        current_.complete = current_started_at_cut_ && largest_gap_ <= max_gap_;
        last_size_ = current_.points.size();
        done.push_back(std::move(current_));
        current_ = Revolution{};
        current_started_at_cut_ = true;
        largest_gap_ = step;  // the gap across the cut belongs to both turns
      }
    }
    has_previous_ = true;
    previous_phase_ = column.phase;
    if (current_.columns == 0) {
      current_.start = column.time;
      // Room for a turn like the last one: no regrowing a multi-megabyte vector every revolution.
      current_.points.reserve(last_size_ + last_size_ / 8);
    }
    current_.end = std::max(current_.end, column.time);
    ++current_.columns;
    current_.rays += column.rays;
    current_.points.insert(current_.points.end(), packet.points.begin() + column.first_point,
                           packet.points.begin() + column.first_point + column.point_count);
  }
}

std::optional<Revolution> RevolutionAssembler::flush() {
  std::optional<Revolution> partial;
  if (current_.columns > 0)
    partial = std::move(current_);
  current_ = Revolution{};
  current_started_at_cut_ = false;
  has_previous_ = false;
  largest_gap_ = 0.0;
  return partial;
}

}  // namespace strata::lidar

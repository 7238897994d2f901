#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/planning/occupancy_grid.hpp"

namespace strata {

inline constexpr double kSqrt2 = 1.4142135623730951;  ///< the cost of a diagonal move

/// Where the robot's centre may be, with the planners' move set. Stored with a one-cell blocked border so a
/// search never checks bounds: a cell's "slot" is its index in that padded array.
///
/// Moves are 8-connected: straight cost 1, diagonal sqrt(2), and a diagonal move only when both orthogonal
/// cells it passes are free (no corner cutting), the rule of the MovingAI/GPPC optimal lengths.
class TraversableGrid {
 public:
  struct Move {
    int offset = 0;  ///< slot difference
    double cost = 1.0;
    int side_a =
        0;  ///< for a diagonal, the slot offsets of the two orthogonal cells it passes; 0 if straight
    int side_b = 0;
    int dx = 0;  ///< the same move in cells
    int dy = 0;
  };

  TraversableGrid() = default;
  /// blocked: one flag per cell of a width x height grid, row-major (as from inflate_obstacles).
  TraversableGrid(int width, int height, const std::vector<std::uint8_t>& blocked);

  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] bool contains(GridCell c) const {
    return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_;
  }
  [[nodiscard]] bool passable(GridCell c) const { return contains(c) && passable_[slot(c)] != 0; }

  [[nodiscard]] int slot(GridCell c) const { return (c.y + 1) * stride_ + c.x + 1; }
  [[nodiscard]] GridCell cell(int slot) const { return {slot % stride_ - 1, slot / stride_ - 1}; }
  [[nodiscard]] int slot_count() const { return stride_ * (height_ + 2); }
  [[nodiscard]] bool passable_slot(int slot) const { return passable_[static_cast<std::size_t>(slot)] != 0; }

  /// Whether the move from a passable slot may be taken (target passable, no corner cut).
  [[nodiscard]] bool allows(int from, const Move& move) const {
    return passable_slot(from + move.offset) &&
           (move.side_a == 0 || (passable_slot(from + move.side_a) && passable_slot(from + move.side_b)));
  }
  [[nodiscard]] const std::array<Move, 8>& moves() const { return moves_; }

 private:
  int width_ = 0;
  int height_ = 0;
  int stride_ = 2;
  std::vector<std::uint8_t> passable_;
  std::array<Move, 8> moves_{};
};

/// Octile distance between cells: the shortest 8-connected path length ignoring obstacles.
[[nodiscard]] inline double octile_distance(GridCell a, GridCell b) {
  const int dx = a.x > b.x ? a.x - b.x : b.x - a.x;
  const int dy = a.y > b.y ? a.y - b.y : b.y - a.y;
  const int diagonal = dx < dy ? dx : dy;
  const int straight = (dx < dy ? dy : dx) - diagonal;
  return straight + kSqrt2 * diagonal;
}

}  // namespace strata

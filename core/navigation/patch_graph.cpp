#include "core/navigation/patch_graph.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace strata {
namespace {

constexpr int kDirections[8][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};

}  // namespace

PatchGraph::PatchGraph(std::shared_ptr<const SurfaceGrid> surfaces, double resolution,
                       const PatchGraphConfig& config)
    : surfaces_(std::move(surfaces)), resolution_(resolution), config_(config) {
  if (config.traversability.unseen_gaps.max_gap > 0.0)
    surfaces_ =
        std::make_shared<const SurfaceGrid>(fill_unseen_gaps(*surfaces_, resolution, config.traversability));
  const SurfaceGrid& grid = *surfaces_;
  const std::size_t count = grid.surface_count();
  cell_of_.resize(count);
  traversable_.assign(count, 0);
  const CellRegion& region = grid.region();
  for (int row = 0; row < region.height; ++row)
    for (int col = 0; col < region.width; ++col) {
      const std::size_t c = grid.cell(col, row);
      const std::uint32_t first = grid.first_surface(c);
      const auto cell_surfaces = grid.surfaces(c);
      for (std::size_t i = 0; i < cell_surfaces.size(); ++i) {
        cell_of_[first + i] = static_cast<std::uint32_t>(c);
        traversable_[first + i] = cell_surfaces[i].traversable ? 1 : 0;  // seams included
      }
    }
  link(config.traversability);
  measure_clearance();
  label_components();
}

void PatchGraph::label_components() {
  component_.assign(neighbours_.size(), kNone);
  std::uint32_t next_label = 0;
  std::vector<Node> stack;
  for (Node seed = 0; seed < neighbours_.size(); ++seed) {
    if (component_[seed] != kNone || !passable(seed))
      continue;
    component_[seed] = next_label;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Node node = stack.back();
      stack.pop_back();
      for (const Node next : neighbours_[node])
        if (next != kNone && component_[next] == kNone && passable(next)) {
          component_[next] = next_label;
          stack.push_back(next);
        }
    }
    ++next_label;
  }
}

std::pair<int, int> PatchGraph::cell(Node node) const {
  const auto width = static_cast<std::uint32_t>(surfaces_->region().width);
  return {static_cast<int>(cell_of_[node] % width), static_cast<int>(cell_of_[node] / width)};
}

Eigen::Vector3d PatchGraph::position(Node node) const {
  const auto [col, row] = cell(node);
  const CellRegion& region = surfaces_->region();
  const std::size_t c = cell_of_[node];
  const float top = surfaces_->surfaces(c)[node - surfaces_->first_surface(c)].top;
  return {(region.min.x + col + 0.5) * resolution_, (region.min.y + row + 0.5) * resolution_,
          static_cast<double>(top)};
}

void PatchGraph::link(const TraversabilityConfig& config) {
  const SurfaceGrid& grid = *surfaces_;
  const CellRegion& region = grid.region();
  const auto robot_height = static_cast<float>(config.robot_height);
  neighbours_.assign(grid.surface_count(), {kNone, kNone, kNone, kNone, kNone, kNone, kNone, kNone});
  // The traversable patch of (col, row) that a patch meets (SurfaceGrid::step_onto).
  const auto meet = [&](int col, int row, const SurfaceGrid::Surface& from) -> Node {
    return grid.step_onto(col, row, from.top, from.variance).value_or(kNone);
  };
  // Whether (col, row) holds something seen at or below a patch at `top`, up to the robot's roof: a wall,
  // a step, lower ground. Without that the cell is unknown at this level (unseen, or only a roof above).
  // Ground inferred across a gap was not seen: the road inferred under a bridge deck is no drop beside
  // the deck's own unseen cells (issue 58).
  const auto seen_at = [&](int col, int row, float top) {
    if (col < 0 || row < 0 || col >= region.width || row >= region.height)
      return false;
    for (const SurfaceGrid::Surface& s : grid.surfaces(grid.cell(col, row)))
      if (!s.inferred && s.bottom <= top + robot_height)
        return true;
    return false;
  };
  // Whether (col, row) holds something seen rising above a patch more than a step, below the robot's roof:
  // a wall, a box, a curb; not lower ground, nor a face reaching up from it.
  const auto rises_at = [&](int col, int row, const SurfaceGrid::Surface& from) {
    if (!grid.contains_local(col, row))
      return false;
    for (const SurfaceGrid::Surface& s : grid.surfaces(grid.cell(col, row)))
      if (!s.inferred && s.bottom <= from.top + robot_height &&
          s.top - from.top > grid.step_limit(from.variance, s.variance))
        return true;
    return false;
  };
  constexpr float kNoSeed = std::numeric_limits<float>::infinity();
  edge_seed_.assign(grid.surface_count(), kNoSeed);
  rising_seed_.assign(grid.surface_count(), kNoSeed);
  missing_seed_.assign(grid.surface_count(), kNoSeed);
  // Beyond a missing side, an edge further than this does not limit the robot's centre.
  const int look_ahead = static_cast<int>(std::ceil(config_.robot_radius / resolution_)) + 1;
  for (int row = 0; row < region.height; ++row)
    for (int col = 0; col < region.width; ++col) {
      const std::size_t c = grid.cell(col, row);
      const std::uint32_t first = grid.first_surface(c);
      const auto cell_surfaces = grid.surfaces(c);
      for (std::size_t i = 0; i < cell_surfaces.size(); ++i) {
        const Node node = first + static_cast<Node>(i);
        if (traversable_[node] == 0)
          continue;
        const SurfaceGrid::Surface& from = cell_surfaces[i];
        const float top = from.top;
        std::array<Node, 8>& out = neighbours_[node];
        for (int d = 0; d < 8; d += 2) {
          const int dx = kDirections[d][0];
          const int dy = kDirections[d][1];
          out[static_cast<std::size_t>(d)] = meet(col + dx, row + dy, from);
        }
        for (int d = 1; d < 8; d += 2) {
          if (out[static_cast<std::size_t>(d - 1)] == kNone ||
              out[static_cast<std::size_t>((d + 1) % 8)] == kNone)
            continue;  // no corner cutting
          out[static_cast<std::size_t>(d)] = meet(col + kDirections[d][0], row + kDirections[d][1], from);
        }
        for (int d = 0; d < 8; ++d) {
          if (out[static_cast<std::size_t>(d)] != kNone)
            continue;
          // The side is half a cell away (a corner: half a diagonal). Past an unseen stretch the clearance
          // still counts what was seen across it, so look on along the direction for an edge.
          const auto side = static_cast<float>(0.5 * step_length(d) * resolution_);
          missing_seed_[node] = std::min(missing_seed_[node], side);
          for (int j = 1; j <= look_ahead; ++j) {
            const int c2 = col + j * kDirections[d][0];
            const int r2 = row + j * kDirections[d][1];
            // The ground goes on past the gap; or, a step away, diagonally across a corner the robot may not
            // cut: the ground a corner cell holds is no edge (the sides say whether something is there).
            if (meet(c2, r2, from) != kNone)
              break;
            const float distance = side + static_cast<float>((j - 1) * step_length(d) * resolution_);
            if (seen_at(c2, r2, top))
              edge_seed_[node] = std::min(edge_seed_[node], distance);
            // Past lower ground, on to the first thing rising above this patch: what the track must keep
            // clear of.
            if (rises_at(c2, r2, from)) {
              rising_seed_[node] = std::min(rising_seed_[node], distance);
              break;
            }
          }
        }
      }
    }
}

void PatchGraph::measure_clearance() {
  clearance_ = spread(edge_seed_);
  // Only ever compared with the robot's radius (passable): spread no further.
  rising_clearance_ = spread(rising_seed_, static_cast<float>(config_.robot_radius + resolution_));
  margin_ = spread(missing_seed_);
  for (std::size_t node = 0; node < margin_.size(); ++node)
    margin_[node] = std::min(margin_[node], clearance_[node]);
}

std::vector<float> PatchGraph::spread(std::vector<float> distance, std::optional<float> horizon_limit) const {
  // Only distances up to the widest one a plan looks at matter (the robot's radius, the comfortable
  // clearance): stopping there keeps the search to a band along the edges instead of all open ground.
  const auto horizon = horizon_limit.value_or(
      static_cast<float>(std::max(config_.robot_radius, config_.comfortable_clearance) + resolution_));
  using Item = std::pair<float, Node>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  for (Node node = 0; node < distance.size(); ++node) {
    if (traversable_[node] == 0)
      distance[node] = 0.0F;
    else if (std::isfinite(distance[node]))
      open.emplace(distance[node], node);
  }
  while (!open.empty()) {
    const auto [reached, node] = open.top();
    open.pop();
    if (reached > distance[node])
      continue;
    const auto& out = neighbours_[node];
    for (int d = 0; d < 8; ++d) {
      const Node next = out[static_cast<std::size_t>(d)];
      if (next == kNone)
        continue;
      const auto candidate = reached + static_cast<float>(step_length(d) * resolution_);
      if (candidate < distance[next] && candidate <= horizon) {
        distance[next] = candidate;
        open.emplace(candidate, next);
      }
    }
  }
  return distance;
}

bool PatchGraph::inferred(Node node) const {
  const std::size_t c = cell_of_[node];
  return surfaces_->surfaces(c)[node - surfaces_->first_surface(c)].inferred;
}

bool PatchGraph::local_cell(double x, double y, int& col, int& row) const {
  const CellRegion& region = surfaces_->region();
  col = static_cast<int>(std::floor(x / resolution_)) - region.min.x;
  row = static_cast<int>(std::floor(y / resolution_)) - region.min.y;
  return std::isfinite(x) && std::isfinite(y) && col >= 0 && row >= 0 && col < region.width &&
         row < region.height;
}

bool PatchGraph::has_patch_near(double x, double y, double z, double tolerance) const {
  int col = 0;
  int row = 0;
  if (!local_cell(x, y, col, row))
    return false;
  for (const SurfaceGrid::Surface& s : surfaces_->surfaces(surfaces_->cell(col, row)))
    if (static_cast<double>(s.bottom) <= z + tolerance && static_cast<double>(s.top) >= z - tolerance)
      return true;
  return false;
}

bool PatchGraph::mapped(double x, double y) const {
  int col = 0;
  int row = 0;
  return local_cell(x, y, col, row) && !surfaces_->surfaces(surfaces_->cell(col, row)).empty();
}

std::optional<PatchGraph::Node> PatchGraph::locate(double x, double y, double z, double tolerance,
                                                   double search_radius) const {
  int col = 0;
  int row = 0;
  if (!local_cell(x, y, col, row))
    return std::nullopt;
  const int rings = static_cast<int>(std::ceil(std::max(search_radius, 0.0) / resolution_));
  return surfaces_->nearest_surface(col, row, z, tolerance, rings, SurfaceGrid::Standing::kTraversable);
}

}  // namespace strata

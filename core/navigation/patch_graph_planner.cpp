#include "core/navigation/patch_graph_planner.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace strata {

namespace {

/// The patch nearest (x, y) in the plane within `radius` metres, within twice the level tolerance of
/// `reference`, with room for the robot and, unless `component` is kNone, in that component.
std::optional<PatchGraph::Node> nearest_with_room(const PatchGraph& graph, double x, double y,
                                                  double reference, double level_tolerance, double radius,
                                                  std::uint32_t component) {
  const SurfaceGrid& grid = graph.surfaces();
  const double resolution = graph.resolution();
  const auto [centre_col, centre_row] = grid.local(
      {static_cast<int>(std::floor(x / resolution)), static_cast<int>(std::floor(y / resolution))});
  const int rings = static_cast<int>(std::ceil(radius / resolution));
  std::optional<PatchGraph::Node> best;
  double best_distance = radius;
  for (int row = centre_row - rings; row <= centre_row + rings; ++row)
    for (int col = centre_col - rings; col <= centre_col + rings; ++col) {
      if (!grid.contains_local(col, row))
        continue;
      const std::size_t c = grid.cell(col, row);
      for (std::uint32_t i = 0; i < grid.surfaces(c).size(); ++i) {
        const PatchGraph::Node node = grid.first_surface(c) + i;
        if (!graph.passable(node) || (component != PatchGraph::kNone && graph.component(node) != component))
          continue;
        const Eigen::Vector3d position = graph.position(node);
        const double distance = std::hypot(position.x() - x, position.y() - y);
        if (std::abs(position.z() - reference) <= 2.0 * level_tolerance && distance < best_distance) {
          best_distance = distance;
          best = node;
        }
      }
    }
  return best;
}

/// The patch with room for the robot nearest (x, y) in the plane within `radius` metres that the ground
/// joins to `from` (over graph edges, through patches too near an edge), in `component` unless kNone: a
/// goal beside a wall moves along its own floor, never down a step or to another level.
std::optional<PatchGraph::Node> room_on_same_ground(const PatchGraph& graph, PatchGraph::Node from, double x,
                                                    double y, double radius, std::uint32_t component) {
  std::optional<PatchGraph::Node> best;
  double best_distance = radius;
  std::vector<PatchGraph::Node> frontier{from};
  std::vector<PatchGraph::Node> visited{from};
  while (!frontier.empty()) {
    const PatchGraph::Node node = frontier.back();
    frontier.pop_back();
    const Eigen::Vector3d position = graph.position(node);
    const double distance = std::hypot(position.x() - x, position.y() - y);
    if (graph.passable(node) && (component == PatchGraph::kNone || graph.component(node) == component) &&
        distance < best_distance) {
      best_distance = distance;
      best = node;
    }
    for (const PatchGraph::Node next : graph.neighbours(node)) {
      if (next == PatchGraph::kNone || std::find(visited.begin(), visited.end(), next) != visited.end())
        continue;
      const Eigen::Vector3d p = graph.position(next);
      if (std::hypot(p.x() - x, p.y() - y) > radius)
        continue;
      visited.push_back(next);
      frontier.push_back(next);
    }
  }
  return best;
}

}  // namespace

std::string_view describe(PatchPlanStatus status) {
  switch (status) {
    case PatchPlanStatus::found:
      return "found";
    case PatchPlanStatus::start_off_map:
      return "the robot is not on a mapped drivable surface";
    case PatchPlanStatus::goal_off_map:
      return "the goal is outside the known map";
    case PatchPlanStatus::goal_blocked:
      return "the goal is not a drivable place with room for the robot";
    case PatchPlanStatus::no_path:
      return "no drivable connection to the goal";
  }
  return "unknown";
}

PatchPath plan_on_patches(const PatchGraph& graph, const Eigen::Vector3d& robot_ground,
                          const PatchGoal& goal) {
  using Node = PatchGraph::Node;
  PatchPath result;
  const TraversabilityConfig& traversability = graph.config().traversability;
  const std::optional<Node> start =
      graph.locate(robot_ground.x(), robot_ground.y(), robot_ground.z(), traversability.start_tolerance,
                   traversability.start_search_radius);
  if (!start) {
    result.status = PatchPlanStatus::start_off_map;
    return result;
  }
  const double reference = goal.z.value_or(robot_ground.z());
  const bool seen_at_level = graph.has_patch_near(goal.x, goal.y, reference, goal.level_tolerance);
  std::optional<Node> target = graph.locate(goal.x, goal.y, reference, goal.level_tolerance,
                                            seen_at_level ? 0.0 : goal.unseen_search_radius);
  if (!target && !goal.z && !seen_at_level)
    target = graph.locate(goal.x, goal.y, reference, std::numeric_limits<double>::infinity());
  if (!target) {
    result.status = graph.mapped(goal.x, goal.y) || seen_at_level ? PatchPlanStatus::goal_blocked
                                                                  : PatchPlanStatus::goal_off_map;
    return result;
  }
  if (!graph.passable(*target)) {
    // Ground, but too near an edge: the nearest place with room, if the goal may move that far.
    const std::uint32_t component = graph.passable(*start) ? graph.component(*start) : PatchGraph::kNone;
    const std::optional<Node> room =
        goal.room_search_radius > 0.0
            ? room_on_same_ground(graph, *target, goal.x, goal.y, goal.room_search_radius, component)
            : std::nullopt;
    if (!room) {
      result.status = PatchPlanStatus::goal_blocked;
      return result;
    }
    target = room;
    result.moved_goal = graph.position(*room);
  }

  if (graph.passable(*start) && graph.component(*start) != graph.component(*target)) {
    result.status = PatchPlanStatus::no_path;  // known without searching
    return result;
  }

  const auto [goal_col, goal_row] = graph.cell(*target);
  const double resolution = graph.resolution();
  const auto heuristic = [&, goal_col = goal_col, goal_row = goal_row](Node node) {
    const auto [col, row] = graph.cell(node);
    const double dx = std::abs(col - goal_col);
    const double dy = std::abs(row - goal_row);
    return resolution * (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));
  };
  const PatchGraphConfig& config = graph.config();
  const double comfort_span = std::max(config.comfortable_clearance - config.robot_radius, 1e-6);
  const auto step_factor = [&](Node node) {
    if (config.clearance_weight <= 0.0)
      return 1.0;
    const double tightness =
        (config.comfortable_clearance - static_cast<double>(graph.margin(node))) / comfort_span;
    return 1.0 + config.clearance_weight * std::clamp(tightness, 0.0, 1.0);
  };
  const std::size_t count = graph.node_count();
  std::vector<double> cost(count, std::numeric_limits<double>::infinity());
  std::vector<Node> parent(count, PatchGraph::kNone);
  using Item = std::pair<double, Node>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  cost[*start] = 0.0;
  open.emplace(heuristic(*start), *start);
  while (!open.empty()) {
    const auto [estimate, node] = open.top();
    open.pop();
    if (estimate - heuristic(node) > cost[node] + 1e-9)
      continue;  // a stale entry
    ++result.expanded;
    if (node == *target)
      break;
    const bool room = graph.passable(node);
    const auto& out = graph.neighbours(node);
    for (int d = 0; d < 8; ++d) {
      const Node next = out[static_cast<std::size_t>(d)];
      if (next == PatchGraph::kNone)
        continue;
      // Into a patch with room, or, while still too near an edge, away from it.
      if (!graph.passable(next) && (room || graph.clearance(next) < graph.clearance(node)))
        continue;
      const double candidate = cost[node] + PatchGraph::step_length(d) * resolution * step_factor(next);
      if (candidate < cost[next]) {
        cost[next] = candidate;
        parent[next] = node;
        open.emplace(candidate + heuristic(next), next);
      }
    }
  }
  if (!std::isfinite(cost[*target])) {
    result.status = PatchPlanStatus::no_path;
    return result;
  }
  for (Node node = *target; node != PatchGraph::kNone; node = parent[node])
    result.points.push_back(graph.position(node));
  std::reverse(result.points.begin(), result.points.end());
  // End where the operator asked, not at the centre of that cell (at most half a cell away); a moved goal
  // ends at the centre of the place with room.
  if (!result.moved_goal)
    result.points.back().head<2>() = Eigen::Vector2d(goal.x, goal.y);
  for (std::size_t i = 1; i < result.points.size(); ++i)
    result.length += (result.points[i] - result.points[i - 1]).head<2>().norm();
  result.status = PatchPlanStatus::found;
  return result;
}

std::optional<Eigen::Vector3d> nearest_reachable(const PatchGraph& graph, const Eigen::Vector3d& robot_ground,
                                                 const PatchGoal& goal, double radius) {
  const TraversabilityConfig& traversability = graph.config().traversability;
  const std::optional<PatchGraph::Node> start =
      graph.locate(robot_ground.x(), robot_ground.y(), robot_ground.z(), traversability.start_tolerance,
                   traversability.start_search_radius);
  if (!start || !graph.passable(*start))
    return std::nullopt;
  const std::optional<PatchGraph::Node> nearest =
      nearest_with_room(graph, goal.x, goal.y, goal.z.value_or(robot_ground.z()), goal.level_tolerance,
                        radius, graph.component(*start));
  if (!nearest)
    return std::nullopt;
  return graph.position(*nearest);
}

}  // namespace strata

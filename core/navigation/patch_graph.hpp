#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/mls/traversability.hpp"
#include "core/mls/unseen_gaps.hpp"

namespace strata {

struct PatchGraphConfig {
  TraversabilityConfig traversability;
  /// Patches whose centre is nearer than this to the edge of their level (a wall, a drop, a step: something
  /// seen) are no place for the robot's centre, metres. The end of the known map is not an edge: unseen
  /// ground is unknown, not an obstacle, and the scans on the way show what it is. The wheelchair's body is
  /// 1.05 x 0.66 m: 0.33 m to its sides, 0.62 m to its corners, so it fits where it drives about straight
  /// (doors, ramps).
  double robot_radius = 0.45;
  /// Paths may keep away from edges and from unseen ground: a step onto a patch with a margin less than
  /// `comfortable_clearance` costs up to (1 + clearance_weight) times its length, so the robot goes through
  /// the middle of doors, approaches them straight and prefers ground it has seen. 0 gives the plain
  /// shortest path.
  double clearance_weight = 0.0;
  double comfortable_clearance = 1.0;
};

/// The drivable surfaces of an MLS map as a graph (docs/architecture.md 4.4, across levels): one node per
/// traversable horizontal patch, an edge to the patch of each of the 8 neighbouring cells that it meets
/// within max_step (diagonals only when both cells beside the diagonal meet it too: no corner cutting).
/// Because nodes are patches, not cells, the deck of a bridge and the road under it are different nodes of
/// the same cell, and the ramp joins them. Each node knows its clearance: the distance along the graph to
/// the nearest edge of its level, so the robot's radius is respected on every level on its own. Which
/// patches are traversable (seams included), which patch a step reaches and where the robot stands are the
/// SurfaceGrid's rules (core/mls/traversability.hpp), shared with the drivable map.
class PatchGraph {
 public:
  using Node = std::uint32_t;
  static constexpr Node kNone = 0xFFFFFFFFU;

  PatchGraph(std::shared_ptr<const SurfaceGrid> surfaces, double resolution, const PatchGraphConfig& config);

  [[nodiscard]] const SurfaceGrid& surfaces() const { return *surfaces_; }
  [[nodiscard]] double resolution() const { return resolution_; }
  [[nodiscard]] const PatchGraphConfig& config() const { return config_; }
  [[nodiscard]] std::size_t node_count() const { return cell_of_.size(); }

  /// The 8 neighbours (kNone where there is no edge), east first, counter-clockwise.
  [[nodiscard]] const std::array<Node, 8>& neighbours(Node node) const { return neighbours_[node]; }
  [[nodiscard]] static double step_length(int direction) {
    return (direction % 2 == 0) ? 1.0 : 1.4142135623730951;
  }
  /// Whether the node is a surface the robot may drive on at all (traversable and horizontal).
  [[nodiscard]] bool traversable(Node node) const { return traversable_[node] != 0; }
  /// Metres from the node's centre to the nearest edge of its level (something seen: a wall, a drop);
  /// exact up to the larger of robot_radius and comfortable_clearance, infinity beyond.
  [[nodiscard]] float clearance(Node node) const { return clearance_[node]; }
  /// Metres from the node's centre to the nearest edge or unseen ground: at most clearance(), likewise.
  [[nodiscard]] float margin(Node node) const { return margin_[node]; }
  /// Whether the node's surface was inferred across an unseen gap rather than measured.
  [[nodiscard]] bool inferred(Node node) const;
  /// Metres from the node's centre to the nearest thing seen rising above it more than a step (a wall, a
  /// box; not lower ground): at least clearance(); exact up to robot_radius, infinity beyond.
  [[nodiscard]] float rising_clearance(Node node) const { return rising_clearance_[node]; }
  /// Whether the robot's centre passed over the node's surface (MlsPatch::kTrack).
  [[nodiscard]] bool on_track(Node node) const { return surfaces_->surface(node).track; }
  /// Traversable with room for the robot: no edge within robot_radius. On the robot's track only what rises
  /// above it counts: the robot fitted there, so lower ground seen beside the track is no edge it could
  /// fall over. Where the pose's height drifted, the track lies 0.1-0.2 m above far views of the same
  /// ground, a step, and a track 2 x driven_radius wide closed the way back (issue 58: the campus bridge
  /// deck between its seams, the lidar demo at 5x stranded on it).
  [[nodiscard]] bool passable(Node node) const {
    const auto radius = static_cast<float>(config_.robot_radius);
    return traversable(node) &&
           (clearance_[node] >= radius || (on_track(node) && rising_clearance_[node] >= radius));
  }
  /// Passable nodes joined by edges between passable nodes share a component; kNone for the others. Two
  /// passable nodes in different components have no path: answered without a search.
  [[nodiscard]] std::uint32_t component(Node node) const { return component_[node]; }
  [[nodiscard]] Eigen::Vector3d position(Node node) const;
  /// Local (col, row) of the node's cell in the surface grid's region.
  [[nodiscard]] std::pair<int, int> cell(Node node) const;

  /// The traversable patch of the cell under (x, y) nearest the height z and within `tolerance` of it,
  /// if any. With `search_radius` > 0 the nearest ring of cells around that has one is taken when the
  /// cell itself has none (the robot's own cell is often unseen): SurfaceGrid::nearest_surface.
  [[nodiscard]] std::optional<Node> locate(double x, double y, double z, double tolerance,
                                           double search_radius = 0.0) const;
  /// Whether the cell under (x, y) has a patch reaching within `tolerance` of the height z (a floor, a wall).
  [[nodiscard]] bool has_patch_near(double x, double y, double z, double tolerance) const;
  /// Whether the cell under (x, y) has any patch, measured or inferred (is mapped).
  [[nodiscard]] bool mapped(double x, double y) const;

 private:
  [[nodiscard]] bool local_cell(double x, double y, int& col, int& row) const;
  void link(const TraversabilityConfig& config);
  void measure_clearance();
  /// Multi-source Dijkstra over the graph from per-node seed distances (infinity: no seed), metres.
  /// Exact up to `horizon` metres (default: the larger of robot_radius and comfortable_clearance), infinity
  /// beyond.
  [[nodiscard]] std::vector<float> spread(std::vector<float> seeds,
                                          std::optional<float> horizon = std::nullopt) const;
  void label_components();

  std::shared_ptr<const SurfaceGrid> surfaces_;
  double resolution_;
  PatchGraphConfig config_;
  std::vector<std::uint32_t> cell_of_;  ///< per node (= surface index): its cell index
  std::vector<std::uint8_t> traversable_;
  std::vector<std::array<Node, 8>> neighbours_;
  std::vector<float> edge_seed_;     ///< per node: metres to the nearest edge seen across its missing sides
  std::vector<float> rising_seed_;   ///< likewise, to the nearest thing rising above it (rises_at)
  std::vector<float> missing_seed_;  ///< per node: metres to its nearest missing side
  std::vector<float> clearance_;
  std::vector<float> rising_clearance_;
  std::vector<float> margin_;
  std::vector<std::uint32_t> component_;
};

}  // namespace strata

#include "core/posegraph/pose_graph.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace strata {
namespace {

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, 0.0);
  return pose;
}

/// A robot driving a 10 m circle in 40 steps, true poses.
std::vector<Eigen::Isometry3d> circle() {
  std::vector<Eigen::Isometry3d> truth;
  for (int i = 0; i < 40; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / 40.0;
    truth.push_back(planar(5.0 * std::cos(angle), 5.0 * std::sin(angle), angle + std::numbers::pi / 2));
  }
  return truth;
}

/// The chain as a drifting odometry measures it: each step's turn 1 degree too far, its length 2 % long.
/// The estimates start where that chain puts them.
PoseGraph drifted_chain(const std::vector<Eigen::Isometry3d>& truth) {
  PoseGraph graph;
  graph.add_node(truth[0]);
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Eigen::Isometry3d step = truth[i - 1].inverse() * truth[i];
    step.translation() *= 1.02;
    step.linear() = step.linear() *
                    Eigen::AngleAxisd(std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    graph.add_node(graph.pose(i - 1) * step);
    PoseGraphEdge edge;
    edge.from = i - 1;
    edge.to = i;
    edge.measurement = step;
    edge.information = PoseInformation::Identity() * 1000.0;  // 3 cm, 0.03 rad: as a scan matcher measures
    graph.add_edge(edge);
  }
  return graph;
}

PoseGraphEdge true_loop(const std::vector<Eigen::Isometry3d>& truth, std::size_t from, std::size_t to) {
  PoseGraphEdge loop;
  loop.from = from;
  loop.to = to;
  loop.measurement = truth[from].inverse() * truth[to];
  loop.information = PoseInformation::Identity() * 400.0;  // 5 cm, 0.05 rad
  loop.loop = true;
  return loop;
}

double worst_error(const PoseGraph& graph, const std::vector<Eigen::Isometry3d>& truth) {
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i)
    worst = std::max(worst, (graph.pose(i).translation() - truth[i].translation()).norm());
  return worst;
}

TEST(PoseGraph, ADriftedLoopIsClosed) {
  const std::vector<Eigen::Isometry3d> truth = circle();
  PoseGraph graph = drifted_chain(truth);
  ASSERT_GT(worst_error(graph, truth), 3.0) << "the chain alone drifts metres";
  graph.add_edge(true_loop(truth, 0, truth.size() - 1));
  const PoseGraphSummary summary = graph.optimize();
  ASSERT_TRUE(summary.solved);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_EQ(summary.loops_dropped, 0U);
  EXPECT_LT((graph.pose(truth.size() - 1).translation() - truth.back().translation()).norm(), 0.1);
  EXPECT_LT(worst_error(graph, truth), 0.5) << "the length error stays, spread along the loop";
  EXPECT_TRUE(graph.pose(0).isApprox(truth[0])) << "the first node holds the map frame";
}

TEST(PoseGraph, AFalseLoopIsDroppedAndTheTrueOnesKept) {
  const std::vector<Eigen::Isometry3d> truth = circle();
  PoseGraph graph = drifted_chain(truth);
  for (std::size_t from : {0U, 2U, 4U})
    graph.add_edge(true_loop(truth, from, truth.size() - 2 + from / 4));
  PoseGraphEdge wrong = true_loop(truth, 10, 30);
  wrong.measurement.translation() += Eigen::Vector3d(3.0, 0.0, 0.0);  // a corridor matched one door off
  graph.add_edge(wrong);
  const PoseGraphSummary summary = graph.optimize();
  ASSERT_TRUE(summary.solved);
  EXPECT_EQ(summary.loops_dropped, 1U);
  EXPECT_EQ(graph.loop_count(), 3U);
  for (const PoseGraphEdge& edge : graph.edges())
    EXPECT_FALSE(edge.loop && edge.from == 10) << "the false loop is gone";
  EXPECT_LT(worst_error(graph, truth), 0.5);
}

TEST(PoseGraph, ADirectionWithoutInformationIsLeftToTheRest) {
  // Two nodes: the odometry-like edge says 1 m along x; a loop that only knows y and z (a corridor along
  // x) claims 5 m along x. With no information along x the loop cannot move the node along it.
  PoseGraph graph;
  graph.add_node(Eigen::Isometry3d::Identity());
  graph.add_node(planar(1.0, 0.0, 0.0));
  PoseGraphEdge odometry;
  odometry.from = 0;
  odometry.to = 1;
  odometry.measurement = planar(1.0, 0.0, 0.0);
  odometry.information = PoseInformation::Identity();
  graph.add_edge(odometry);
  PoseGraphEdge corridor;
  corridor.from = 0;
  corridor.to = 1;
  corridor.measurement = planar(5.0, 0.2, 0.0);
  corridor.information = PoseInformation::Identity() * 1e4;
  corridor.information(0, 0) = 0.0;
  graph.add_edge(corridor);
  ASSERT_TRUE(graph.optimize().solved);
  EXPECT_NEAR(graph.pose(1).translation().x(), 1.0, 1e-3);
  EXPECT_NEAR(graph.pose(1).translation().y(), 0.2, 1e-3);
}

TEST(PoseGraph, AnAttitudePriorLevelsATiltedChain) {
  // Each step measured with a pitch of 1 degree too many: without gravity the chain climbs.
  PoseGraph graph;
  graph.add_node(Eigen::Isometry3d::Identity());
  Eigen::Isometry3d step = planar(1.0, 0.0, 0.0);
  step.linear() = Eigen::AngleAxisd(-std::numbers::pi / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (std::size_t i = 1; i <= 20; ++i) {
    graph.add_node(graph.pose(i - 1) * step);
    PoseGraphEdge edge;
    edge.from = i - 1;
    edge.to = i;
    edge.measurement = step;
    edge.information = PoseInformation::Identity() * 100.0;
    graph.add_edge(edge);
    graph.add_prior({.node = i, .up_in_body = Eigen::Vector3d::UnitZ(), .sigma = 0.002});
  }
  ASSERT_GT(graph.pose(20).translation().z(), 3.0);
  ASSERT_TRUE(graph.optimize().solved);
  EXPECT_LT(std::abs(graph.pose(20).translation().z()), 0.5);
}

TEST(PoseGraph, AnOutAndBackTellsTheGravitySensorsMountingError) {
  // 30 m out along x and 30 m back 2 m beside it, on flat ground, loops across. The gravity sensor is
  // mounted tilted (about the body's x and y): driven straight, its readings tilt the map with them; out
  // and back they tilt it opposite ways, which the loops forbid.
  const Eigen::Vector3d mounting(0.002, -0.003, 0.0);  // radians: 0.11 and 0.17 degrees
  std::vector<Eigen::Isometry3d> truth;
  for (int i = 0; i <= 30; ++i)
    truth.push_back(planar(i, 0.0, 0.0));
  for (int i = 30; i >= 0; --i)
    truth.push_back(planar(i, 2.0, std::numbers::pi));
  const auto optimized = [&](double mounting_sigma) {
    PoseGraph graph;
    graph.add_node(truth[0]);
    for (std::size_t i = 1; i < truth.size(); ++i) {
      graph.add_node(truth[i]);
      PoseGraphEdge chain;
      chain.from = i - 1;
      chain.to = i;
      chain.measurement = truth[i - 1].inverse() * truth[i];
      chain.information = PoseInformation::Identity() * 1e4;
      chain.information(3, 3) = chain.information(4, 4) = 1.0 / (0.002 * 0.002);  // the tilt walks a little
      graph.add_edge(chain);
    }
    for (std::size_t out = 2; out <= 28; out += 2) {
      const std::size_t back = truth.size() - 1 - out;
      graph.add_edge(true_loop(truth, out, back));
    }
    const Eigen::Matrix3d tilted =
        Eigen::AngleAxisd(mounting.norm(), mounting.normalized()).toRotationMatrix();
    for (std::size_t i = 1; i < truth.size(); ++i)
      graph.add_prior({.node = i,
                       .up_in_body = tilted * truth[i].linear().transpose() * Eigen::Vector3d::UnitZ(),
                       .sigma = 0.01});
    PoseGraphOptions options;
    options.mounting_sigma = mounting_sigma;
    EXPECT_TRUE(graph.optimize(options).solved);
    return graph;
  };
  const auto worst_height = [&](const PoseGraph& graph) {
    double worst = 0.0;
    for (std::size_t i = 0; i < truth.size(); ++i)
      worst = std::max(worst, std::abs(graph.pose(i).translation().z()));
    return worst;
  };

  const PoseGraph held = optimized(0.0);
  EXPECT_EQ(held.mounting_error(), Eigen::Vector3d::Zero()) << "held where it was";
  const PoseGraph estimated = optimized(0.01);
  EXPECT_NEAR(estimated.mounting_error().x(), mounting.x(), 2e-4);
  EXPECT_NEAR(estimated.mounting_error().y(), mounting.y(), 2e-4);
  EXPECT_EQ(estimated.mounting_error().z(), 0.0);
  EXPECT_GT(worst_height(held), 0.01) << "the readings tilt the map where nothing tells their error";
  EXPECT_LT(worst_height(estimated), 0.2 * worst_height(held));
}

}  // namespace
}  // namespace strata

#include "drivers/lidar/revolution_assembler.hpp"

#include <gtest/gtest.h>

namespace strata::lidar {
namespace {

/// A packet of `count` columns, phases from `first` in `step`s (wrapping at 1), one point each.
DecodedPacket columns(double first, double step, int count, double time) {
  DecodedPacket packet;
  for (int i = 0; i < count; ++i) {
    double phase = first + step * i;
    phase -= std::floor(phase);
    packet.columns.push_back(LidarColumn{time + 0.001 * i, static_cast<float>(phase),
                                         static_cast<std::uint32_t>(packet.points.size()), 1, 16});
    packet.points.push_back(LidarPoint{Eigen::Vector3f::UnitX(), 0.0f, time + 0.001 * i, 0});
  }
  return packet;
}

TEST(RevolutionAssembler, CutsAtThePhaseWrapAndFlagsPartialEnds) {
  RevolutionAssembler assembler;
  std::vector<Revolution> done;
  // Starts mid-turn at 0.5, then two full turns of 100 columns, then half a turn.
  assembler.add(columns(0.5, 0.01, 50, 0.0), done);
  EXPECT_TRUE(done.empty());
  assembler.add(columns(0.0, 0.01, 100, 1.0), done);
  assembler.add(columns(0.0, 0.01, 100, 2.0), done);
  assembler.add(columns(0.0, 0.01, 50, 3.0), done);
  ASSERT_EQ(done.size(), 3u);
  EXPECT_FALSE(done[0].complete);
  EXPECT_EQ(done[0].columns, 50u);
  EXPECT_TRUE(done[1].complete);
  EXPECT_TRUE(done[2].complete);
  EXPECT_EQ(done[1].points.size(), 100u);
  EXPECT_EQ(done[1].rays, 1600u);
  EXPECT_DOUBLE_EQ(done[1].start, 1.0);
  EXPECT_NEAR(done[1].end, 1.099, 1e-9);
  const std::optional<Revolution> last = assembler.flush();
  ASSERT_TRUE(last);
  EXPECT_FALSE(last->complete);
  EXPECT_EQ(last->columns, 50u);
  EXPECT_FALSE(assembler.flush());
}

TEST(RevolutionAssembler, ATurnWithDroppedPacketsIsNotComplete) {
  RevolutionAssembler assembler;
  std::vector<Revolution> done;
  assembler.add(columns(0.9, 0.01, 10, 0.0), done);
  assembler.add(columns(0.0, 0.01, 40, 1.0), done);
  assembler.add(columns(0.6, 0.01, 40, 1.5), done);  // 0.40 .. 0.59 lost
  assembler.add(columns(0.0, 0.01, 10, 2.0), done);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_FALSE(done[1].complete);
  // Small backward steps (reordered packets) are not cuts.
  assembler.add(columns(0.2, 0.01, 10, 3.0), done);
  assembler.add(columns(0.15, 0.01, 10, 3.1), done);
  EXPECT_EQ(done.size(), 2u);
}

}  // namespace
}  // namespace strata::lidar

// The level rule (docs/fleet.md): each 2.5 m band of ground height is its own VDA 5050 mapId,
// "<map>@<level>".
#include "server/fleet/map_id.hpp"

#include <gtest/gtest.h>

namespace strata::fleet {
namespace {

TEST(MapId, LevelsAreBandsOfGroundHeight) {
  EXPECT_EQ(level_of(0.0), 0);
  EXPECT_EQ(level_of(0.45), 0);   // the campus building's floor
  EXPECT_EQ(level_of(1.2), 0);    // low on the ramp
  EXPECT_EQ(level_of(1.3), 1);    // past halfway up to the bridge deck
  EXPECT_EQ(level_of(3.0), 1);    // the deck
  EXPECT_EQ(level_of(-2.6), -1);  // a basement
  EXPECT_DOUBLE_EQ(level_height(1), 2.5);
}

TEST(MapId, IdsReadBack) {
  EXPECT_EQ(map_id("campus", 1), "campus@1");
  EXPECT_EQ(map_id("", 0), "~live@0");
  const auto level = parse_map_id("campus@-1");
  ASSERT_TRUE(level);
  EXPECT_EQ(level->map_name, "campus");
  EXPECT_EQ(level->level, -1);
  EXPECT_EQ(parse_map_id("~live@0")->map_name, "~live");
  for (const char* wrong : {"campus", "campus@", "@1", "campus@x", "cam/pus@1", "campus@1.5", "campus@999"})
    EXPECT_FALSE(parse_map_id(wrong)) << wrong;
}

}  // namespace
}  // namespace strata::fleet

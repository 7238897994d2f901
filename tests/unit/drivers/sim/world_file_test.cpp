#include "drivers/sim/world/world_file.hpp"

#include <gtest/gtest.h>

namespace strata::sim {
namespace {

std::string error_of(const std::string& text) {
  try {
    (void)parse_world(text, "test.json");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "<no error>";
}

TEST(WorldFile, ReadsEveryShapeType) {
  const auto world = parse_world(R"({
    "name": "t", "spawn": {"x": 1, "y": 2, "yaw_deg": 90, "z": 0.5},
    "terrain": {"origin": [0, 0], "size": [4, 2], "cell": 1, "hills": [{"center": [2, 1], "radius": 1, "height": 0.5}]},
    "shapes": [
      {"type": "box", "min": [0, 0, 0], "max": [1, 2, 3]},
      {"type": "box", "center": [5, 5, 1], "size": [1, 1, 2], "yaw_deg": 30},
      {"type": "ramp", "center": [0, 0], "length": 4, "width": 1, "height_start": 0, "height_end": 0.4},
      {"type": "stairs", "start": [0, 0], "width": 1, "steps": 3, "rise": 0.15, "run": 0.3},
      {"type": "cylinder", "center": [1, 1], "radius": 0.1, "z_max": 2},
      {"type": "sphere", "center": [1, 1, 3], "radius": 1},
      {"type": "tree", "at": [3, 3]}
    ],
    "route": [[0, 0], [1, 1]]
  })",
                                 "t.json");
  EXPECT_EQ(world.name, "t");
  EXPECT_DOUBLE_EQ(world.spawn.y, 2.0);
  EXPECT_NEAR(world.spawn.theta, 3.14159265358979 / 2, 1e-12);
  EXPECT_DOUBLE_EQ(world.spawn_z, 0.5);
  ASSERT_EQ(world.boxes.size(), 2u + 3u);  // two boxes and three stair steps
  EXPECT_EQ(world.boxes[0].center, Eigen::Vector3d(0.5, 1, 1.5));
  EXPECT_NEAR(world.boxes[4].size.z(), 0.45, 1e-12);  // the top step stands 3 x 0.15 high
  EXPECT_EQ(world.ramps.size(), 1u);
  EXPECT_EQ(world.cylinders.size(), 2u);  // one cylinder, one trunk
  EXPECT_EQ(world.spheres.size(), 2u);    // one sphere, one crown
  ASSERT_TRUE(world.terrain);
  EXPECT_EQ(world.terrain->nx(), 5);
  EXPECT_NEAR(world.terrain->height(2, 1), 0.5, 1e-12);  // the hill's top
  EXPECT_EQ(world.route.size(), 2u);
}

TEST(WorldFile, ErrorsNameTheFileAndTheEntry) {
  EXPECT_NE(error_of("{ nope").find("test.json: not valid JSON"), std::string::npos);
  EXPECT_NE(error_of(R"({"shapes": [{"type": "blob"}]})").find("test.json.shapes[0]: unknown \"type\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"shapes": [{"type": "box", "min": [0,0,0]}]})").find("missing \"max\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"shapes": [{"type": "box", "min": [0,0,0], "max": [1,-1,1]}]})").find("must exceed"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"shapes": [{"type": "cylinder", "center": [0,0], "radius": -1, "z_max": 1}]})")
                .find("\"radius\" must be positive"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"shapes": [{"type": "box", "min": [0,0,0], "max": [1,1,"x"]}]})")
                .find("must hold numbers"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"shapes": [{"type":"sphere","center":[0,0,0],"radius":1}], "route": [[0, 0]]})")
                .find("at least two points"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"name": "empty"})").find("no shapes"), std::string::npos);
  EXPECT_NE(error_of("[]").find("must be an object"), std::string::npos);
}

TEST(WorldFile, MissingFileIsAClearError) {
  EXPECT_THROW((void)load_world_file("/nonexistent/world.json"), std::runtime_error);
}

TEST(WorldFile, BuiltInWorldsLoad) {
  const auto names = builtin_world_names();
  ASSERT_GE(names.size(), 2u);
  for (const auto& name : names) {
    const World world(builtin_world(name));
    EXPECT_EQ(world.description().name, name);
    EXPECT_GE(world.description().route.size(), 2u) << name;
  }
  EXPECT_THROW((void)builtin_world_text("atlantis"), std::invalid_argument);
}

}  // namespace
}  // namespace strata::sim

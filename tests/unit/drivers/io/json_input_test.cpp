#include "drivers/io/json_input.hpp"

#include <gtest/gtest.h>

#include <string>

namespace strata::io {
namespace {

std::string nested(std::size_t depth) {
  return std::string(depth, '[') + std::string(depth, ']');
}

TEST(JsonInput, ParsesADocumentWithinTheBound) {
  const auto input = parse_json(R"({"a":[1,{"b":null}],"c":"d"})");
  ASSERT_TRUE(input.ok()) << input.error;
  EXPECT_EQ(input.value["a"][1]["b"], nullptr);
  EXPECT_TRUE(parse_json(nested(kMaxJsonDepth)).ok());
}

TEST(JsonInput, RefusesOneLevelTooDeepAndAHundredThousand) {
  EXPECT_EQ(parse_json(nested(kMaxJsonDepth + 1)).error, "nested deeper than 64 levels");
  const auto bomb = parse_json(nested(100000));
  EXPECT_FALSE(bomb.ok());
  EXPECT_TRUE(bomb.value.is_null());
  EXPECT_EQ(parse_json(R"({"a":)" + nested(3) + "}", 3).error, "nested deeper than 3 levels");
}

TEST(JsonInput, SaysWhereTheSyntaxFailsWithoutEchoingIt) {
  const auto broken = parse_json(R"({"secret-token-xyz" 1})");
  EXPECT_FALSE(broken.ok());
  EXPECT_NE(broken.error.find("not valid JSON (at byte"), std::string::npos) << broken.error;
  EXPECT_EQ(broken.error.find("secret"), std::string::npos);
  EXPECT_FALSE(parse_json("").ok());
}

}  // namespace
}  // namespace strata::io

#include "server/control/error_code.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace strata {
namespace {

constexpr ErrorCode kEveryCode[] = {
    ErrorCode::kBadJson,          ErrorCode::kBadMessage,   ErrorCode::kUnknownOp,   ErrorCode::kNotFound,
    ErrorCode::kMethodNotAllowed, ErrorCode::kBadRequest,   ErrorCode::kUnavailable, ErrorCode::kBadParams,
    ErrorCode::kUnauthorized,     ErrorCode::kRateLimited,  ErrorCode::kForbidden,   ErrorCode::kCorruptFile,
    ErrorCode::kIoError,          ErrorCode::kStaleCommand, ErrorCode::kInternal,
};

std::set<std::string> schema_codes(const std::string& schema) {
  std::ifstream file(std::filesystem::path(STRATA_SOURCE_DIR) / "proto" / "schemas" / schema);
  const auto json = nlohmann::json::parse(file);
  const auto& properties = json.contains("properties") && json["properties"].contains("error")
                               ? json["properties"]["error"]["properties"]
                               : json["properties"];
  return properties["code"]["enum"].get<std::set<std::string>>();
}

TEST(ErrorCode, EveryCodeHasItsOwnNameInTheProtocol) {
  // One enum for the WebSocket, REST and the commands behind both: the names are the wire's.
  const auto websocket = schema_codes("ws-server/error.schema.json");
  const auto rest = schema_codes("rest/error.schema.json");
  std::set<std::string> names;
  for (const ErrorCode code : kEveryCode) {
    const std::string name(to_string(code));
    EXPECT_TRUE(names.insert(name).second) << name << " twice";
    EXPECT_TRUE(websocket.count(name) + rest.count(name) > 0) << name << " is in neither error schema";
  }
  for (const auto& name : websocket)
    EXPECT_EQ(names.count(name), 1U) << name << " (ws-server schema) is no ErrorCode";
  for (const auto& name : rest)
    EXPECT_EQ(names.count(name), 1U) << name << " (rest schema) is no ErrorCode";
  EXPECT_EQ(to_string(ErrorCode::kIoError), "io_error");
  EXPECT_EQ(to_string(ErrorCode::kCorruptFile), "corrupt_file");
}

}  // namespace
}  // namespace strata

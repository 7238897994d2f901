#pragma once

// Validates what the server sends against the JSON Schemas in proto/: the contract is tested, not
// restated in the tests. The validator (valijson, heavy templates) lives in protocol_schemas.cpp so that
// it is compiled once, not in every test file.

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

namespace strata::testing {

class ProtocolSchemas {
 public:
  ProtocolSchemas();
  ~ProtocolSchemas();
  ProtocolSchemas(const ProtocolSchemas&) = delete;
  ProtocolSchemas& operator=(const ProtocolSchemas&) = delete;

  /// Empty when `value` matches `proto/schemas/<group>/<name>.schema.json` (groups: ws-server, ws-client,
  /// rest; loaded on first use); otherwise the reasons, one per line. Throws std::runtime_error when there
  /// is no such schema.
  std::string violations(const std::string& group, const std::string& name, const nlohmann::json& value);

  /// For a WebSocket message from the server: picks the schema by its op.
  std::string server_message_violations(const nlohmann::json& message);

 private:
  struct LoadedSchemas;
  std::unique_ptr<LoadedSchemas> loaded_;
};

}  // namespace strata::testing

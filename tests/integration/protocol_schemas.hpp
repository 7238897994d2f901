#pragma once

// Validates what the server sends against the JSON Schemas in proto/: the contract is tested, not
// restated in the tests.

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

namespace strata::testing {

class ProtocolSchemas {
 public:
  /// Loads `proto/schemas/<group>/<name>.schema.json` on first use; groups: ws-server, ws-client, rest.
  const valijson::Schema& schema(const std::string& group, const std::string& name) {
    const std::string key = group + "/" + name;
    auto found = schemas_.find(key);
    if (found != schemas_.end())
      return *found->second;
    const std::filesystem::path file =
        std::filesystem::path(STRATA_PROTO_DIR) / "schemas" / (key + ".schema.json");
    std::ifstream stream(file);
    if (!stream)
      throw std::runtime_error("no schema " + file.string());
    const nlohmann::json document = nlohmann::json::parse(stream);
    auto schema = std::make_unique<valijson::Schema>();
    valijson::SchemaParser parser;
    valijson::adapters::NlohmannJsonAdapter adapter(document);
    parser.populateSchema(adapter, *schema);
    return *schemas_.emplace(key, std::move(schema)).first->second;
  }

  /// Empty when `value` matches the schema; otherwise the reasons, one per line.
  std::string violations(const std::string& group, const std::string& name, const nlohmann::json& value) {
    valijson::Validator validator;
    valijson::ValidationResults results;
    valijson::adapters::NlohmannJsonAdapter target(value);
    if (validator.validate(schema(group, name), target, &results))
      return {};
    std::ostringstream out;
    valijson::ValidationResults::Error error;
    while (results.popError(error)) {
      std::string where;
      for (const auto& part : error.context)
        where += part;
      out << where << ": " << error.description << "\n";
    }
    return out.str();
  }

  /// For a WebSocket message from the server: picks the schema by its op.
  std::string server_message_violations(const nlohmann::json& message) {
    if (!message.is_object() || !message.contains("op") || !message["op"].is_string()) {
      return "not an object with a string op: " + message.dump();
    }
    return violations("ws-server", message["op"].get<std::string>(), message);
  }

 private:
  std::map<std::string, std::unique_ptr<valijson::Schema>> schemas_;
};

}  // namespace strata::testing

#include "integration/protocol_schemas.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

namespace strata::testing {

struct ProtocolSchemas::LoadedSchemas {
  std::map<std::string, std::unique_ptr<valijson::Schema>> by_key;  ///< "group/name"

  const valijson::Schema& schema(const std::string& group, const std::string& name) {
    const std::string key = group + "/" + name;
    auto found = by_key.find(key);
    if (found != by_key.end())
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
    return *by_key.emplace(key, std::move(schema)).first->second;
  }
};

ProtocolSchemas::ProtocolSchemas() : loaded_(std::make_unique<LoadedSchemas>()) {}
ProtocolSchemas::~ProtocolSchemas() = default;

std::string ProtocolSchemas::violations(const std::string& group, const std::string& name,
                                        const nlohmann::json& value) {
  valijson::Validator validator;
  valijson::ValidationResults results;
  valijson::adapters::NlohmannJsonAdapter target(value);
  if (validator.validate(loaded_->schema(group, name), target, &results))
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

std::string ProtocolSchemas::server_message_violations(const nlohmann::json& message) {
  if (!message.is_object() || !message.contains("op") || !message["op"].is_string())
    return "not an object with a string op: " + message.dump();
  return violations("ws-server", message["op"].get<std::string>(), message);
}

}  // namespace strata::testing

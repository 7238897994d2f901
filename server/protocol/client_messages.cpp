#include "server/protocol/client_messages.hpp"

#include <spdlog/fmt/fmt.h>

#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>

#include "drivers/io/json_input.hpp"

namespace strata::protocol {
namespace {

using nlohmann::json;

constexpr std::array<std::pair<std::string_view, Stream>, 6> kStreamNames{{
    {"pose", Stream::kPose},
    {"status", Stream::kStatus},
    {"tiles", Stream::kTiles},
    {"occupancy", Stream::kOccupancy},
    {"path", Stream::kPath},
    {"goal", Stream::kGoal},
}};

/// Fails a message: the error a client gets back.
struct Invalid {
  std::string message;
};

/// Every field of `message` must be one of `allowed` ("op" and "id" always are).
void only_fields(const json& message, std::initializer_list<std::string_view> allowed) {
  for (const auto& [key, value] : message.items()) {
    if (key == "op" || key == "id")
      continue;
    bool known = false;
    for (const auto name : allowed)
      known = known || key == name;
    if (!known)
      throw Invalid{"unknown field \"" + key + "\""};
  }
}

double number(const json& message, const char* name, double limit, bool required = true,
              double fallback = 0.0) {
  const auto found = message.find(name);
  if (found == message.end()) {
    if (required)
      throw Invalid{std::string("missing field \"") + name + "\""};
    return fallback;
  }
  if (!found->is_number())
    throw Invalid{std::string("\"") + name + "\" must be a number"};
  const double value = found->get<double>();
  if (!std::isfinite(value) || std::abs(value) > limit)
    throw Invalid{fmt::format("\"{}\" must be a finite number from -{:g} to {:g}", name, limit, limit)};
  return value;
}

/// A client's value quoted in an error message: short, whatever it was.
std::string quoted_briefly(const json& value) {
  if (!value.is_primitive())
    return value.is_array() ? "(an array)" : "(an object)";
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  constexpr std::size_t kMaxQuoted = 40;
  if (text.size() > kMaxQuoted)
    text = text.substr(0, kMaxQuoted) + "...";
  return text;
}

std::string map_name(const json& message) {
  const auto found = message.find("name");
  if (found == message.end() || !found->is_string())
    throw Invalid{"\"name\" must be a string"};
  const auto name = found->get<std::string>();
  if (!is_valid_map_name(name))
    throw Invalid{"\"name\" must be 1-64 characters of A-Z a-z 0-9 . _ - and not start with a dot"};
  return name;
}

ClientRequest parse_request(const std::string& op, const json& message) {
  if (op == "ping") {
    only_fields(message, {});
    return PingRequest{};
  }
  if (op == "subscribe") {
    only_fields(message, {"streams"});
    const auto found = message.find("streams");
    if (found == message.end() || !found->is_array())
      throw Invalid{"\"streams\" must be an array of stream names"};
    SubscribeRequest request{0};
    for (const auto& item : *found) {
      const auto stream = item.is_string() ? stream_from_name(item.get<std::string>()) : std::nullopt;
      if (!stream)
        throw Invalid{"unknown stream " + quoted_briefly(item) +
                      " (pose, status, tiles, occupancy, path, goal)"};
      request.streams |= static_cast<StreamSet>(*stream);
    }
    return request;
  }
  if (op == "set_goal") {
    only_fields(message, {"x", "y", "z"});
    SetGoalRequest request;
    request.goal.x = number(message, "x", kMaxCoordinate);
    request.goal.y = number(message, "y", kMaxCoordinate);
    if (message.contains("z"))
      request.goal.z = number(message, "z", kMaxCoordinate);
    return request;
  }
  if (op == "set_pose") {
    only_fields(message, {"x", "y", "yaw", "z"});
    SetPoseRequest request;
    request.estimate.x = number(message, "x", kMaxCoordinate);
    request.estimate.y = number(message, "y", kMaxCoordinate);
    request.estimate.yaw = number(message, "yaw", 2.0 * std::numbers::pi);
    if (message.contains("z"))
      request.estimate.z = number(message, "z", kMaxCoordinate);
    return request;
  }
  if (op == "cancel_goal") {
    only_fields(message, {});
    return CancelGoalRequest{};
  }
  if (op == "teleop") {
    only_fields(message, {"v", "w", "seq", "t"});
    TeleopRequest request{number(message, "v", kMaxTeleopSpeed), number(message, "w", kMaxTeleopTurn)};
    if (message.contains("seq") != message.contains("t"))
      throw Invalid{"\"seq\" and \"t\" come together"};
    if (message.contains("seq")) {
      const auto& seq = message.at("seq");
      if (!seq.is_number_unsigned() && !(seq.is_number_integer() && seq.get<std::int64_t>() >= 0))
        throw Invalid{"\"seq\" must be an integer from 0"};
      request.stamp = TeleopStamp{seq.get<std::uint64_t>(), number(message, "t", kMaxClockMs)};
    }
    return request;
  }
  if (op == "save_map") {
    only_fields(message, {"name"});
    return SaveMapRequest{map_name(message)};
  }
  if (op == "load_map") {
    only_fields(message, {"name", "mode"});
    LoadMapRequest request{map_name(message)};
    if (const auto mode = message.find("mode"); mode != message.end()) {
      const std::optional<MapMode> parsed =
          mode->is_string() ? map_mode_from_string(mode->get<std::string>()) : std::nullopt;
      if (!parsed)
        throw Invalid{"\"mode\" must be \"mapping\" or \"localize\""};
      request.mode = *parsed;
    }
    return request;
  }
  throw std::out_of_range(op);
}

}  // namespace

std::optional<Stream> stream_from_name(std::string_view name) {
  for (const auto& [known, stream] : kStreamNames) {
    if (known == name)
      return stream;
  }
  return std::nullopt;
}

bool is_valid_map_name(std::string_view name) {
  if (name.empty() || name.size() > 64 || name.front() == '.')
    return false;
  for (const char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '_' || c == '-';
    if (!ok)
      return false;
  }
  return true;
}

ParsedClientMessage parse_client_message(std::string_view text) {
  const io::JsonInput input = io::parse_json(text);
  if (!input.ok()) {
    ParsedClientMessage parsed;
    parsed.error = ErrorCode::kBadJson;
    parsed.error_message = "message is " + input.error;
    return parsed;
  }
  return validate_client_message(input.value);
}

ParsedClientMessage validate_client_message(const json& message) {
  ParsedClientMessage parsed;
  const auto op = message.is_object() ? message.find("op") : message.end();
  if (!message.is_object() || op == message.end() || !op->is_string()) {
    parsed.error = ErrorCode::kBadMessage;
    parsed.error_message = "a message is a JSON object with a string \"op\"";
    return parsed;
  }
  parsed.op = op->get<std::string>();
  if (const auto id = message.find("id"); id != message.end()) {
    if (!id->is_primitive()) {
      parsed.error = ErrorCode::kBadParams;
      parsed.error_message = "\"id\" must be a string, number, boolean or null";
      return parsed;
    }
    parsed.id = *id;
  }
  try {
    parsed.request = parse_request(parsed.op, message);
  } catch (const Invalid& invalid) {
    parsed.error = ErrorCode::kBadParams;
    parsed.error_message = parsed.op + ": " + invalid.message;
  } catch (const std::out_of_range&) {
    parsed.error = ErrorCode::kUnknownOp;
    parsed.error_message = "unknown op \"" + parsed.op + "\"";
  }
  return parsed;
}

bool needs_operator(const ClientRequest& request) {
  return std::holds_alternative<SetGoalRequest>(request) ||
         std::holds_alternative<CancelGoalRequest>(request) ||
         std::holds_alternative<TeleopRequest>(request) || std::holds_alternative<SaveMapRequest>(request) ||
         std::holds_alternative<LoadMapRequest>(request) || std::holds_alternative<SetPoseRequest>(request);
}

}  // namespace strata::protocol

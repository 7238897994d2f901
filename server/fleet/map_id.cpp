#include "server/fleet/map_id.hpp"

#include <charconv>
#include <cmath>

#include "server/protocol/client_messages.hpp"

namespace strata::fleet {

int level_of(double z) {
  return static_cast<int>(std::lround(z / kLevelHeight));
}

double level_height(int level) {
  return level * kLevelHeight;
}

std::string map_id(std::string_view map_name, int level) {
  return std::string(map_name.empty() ? kUnsavedMapName : map_name) + "@" + std::to_string(level);
}

std::optional<MapLevel> parse_map_id(std::string_view map_id) {
  const auto at = map_id.rfind('@');
  if (at == std::string_view::npos)
    return std::nullopt;
  const std::string_view name = map_id.substr(0, at);
  const std::string_view number = map_id.substr(at + 1);
  if (name != kUnsavedMapName && !protocol::is_valid_map_name(name))
    return std::nullopt;
  int level = 0;
  const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), level);
  if (number.empty() || error != std::errc() || end != number.data() + number.size() || level < -100 ||
      level > 100)
    return std::nullopt;
  return MapLevel{std::string(name), level};
}

}  // namespace strata::fleet

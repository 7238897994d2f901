#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace strata::fleet {

/// VDA 5050 positions are 2-D and "each floor has its own map"; Strata's map is 3-D with levels. The rule
/// (docs/fleet.md, "Levels and mapId"): a level is a 2.5 m band of ground height, centred on 0 m, 2.5 m,
/// ... (level 0 from -1.25 to 1.25 m: a ramp up to a deck at 3 m changes level halfway up), and its mapId
/// is the map's name, '@' and the level's number: "yard@0", "campus@1", "campus@-1". Map names never hold
/// '@' (protocol::is_valid_map_name), so the id reads back unambiguously. A map never saved or loaded is
/// "~live" (no saved name starts with '~').
inline constexpr double kLevelHeight = 2.5;  ///< m: a storey
inline constexpr std::string_view kUnsavedMapName = "~live";

/// The level of ground at height `z`, m.
[[nodiscard]] int level_of(double z);
/// The ground height a level is centred on, m.
[[nodiscard]] double level_height(int level);

struct MapLevel {
  std::string map_name;  ///< a saved map's name, or kUnsavedMapName
  int level = 0;
};

/// "<map name>@<level>"; an empty name is kUnsavedMapName's.
[[nodiscard]] std::string map_id(std::string_view map_name, int level);
/// The map and level a mapId names; none when it is not one of this rule's.
[[nodiscard]] std::optional<MapLevel> parse_map_id(std::string_view map_id);

}  // namespace strata::fleet

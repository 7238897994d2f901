#pragma once

#include <memory>
#include <utility>

#include "drivers/sim/world/world.hpp"

namespace strata::test {

/// A straight corridor 2.5 m wide and 200 m long along x, walls 3 m high, the robot driving its length from
/// x = -20 m to `end`: every scan slides along its axis, and its walls hold the heading.
inline std::shared_ptr<const sim::World> corridor_world(bool ceiling = false, double end = 20.0) {
  sim::WorldDescription corridor;
  corridor.boxes.push_back({"floor", {0, 0, -0.1}, {200, 4, 0.2}, 0.0});
  corridor.boxes.push_back({"wall-left", {0, 1.35, 1.5}, {200, 0.2, 3}, 0.0});
  corridor.boxes.push_back({"wall-right", {0, -1.35, 1.5}, {200, 0.2, 3}, 0.0});
  if (ceiling)
    corridor.boxes.push_back({"ceiling", {0, 0, 3.1}, {200, 4, 0.2}, 0.0});
  corridor.spawn = {-20, 0, 0};
  corridor.route = {{end, 0}, {end + 1.0, 0}};
  return std::make_shared<const sim::World>(std::move(corridor));
}

}  // namespace strata::test

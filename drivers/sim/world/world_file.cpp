#include "drivers/sim/world/world_file.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "core/geometry/angles.hpp"
#include "drivers/io/json_input.hpp"
#include "drivers/sim/world/embedded_worlds.hpp"

namespace strata::sim {
namespace {

using nlohmann::json;

double degrees(double value) {
  return value * kPi / 180.0;
}

// Reads typed fields of one JSON object and names the object in every error.
class Fields {
 public:
  Fields(const json& object, std::string where) : object_(object), where_(std::move(where)) {
    if (!object_.is_object())
      fail("must be an object");
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw std::runtime_error(where_ + ": " + problem);
  }
  [[nodiscard]] bool has(const char* key) const { return object_.contains(key); }

  double number(const char* key) const {
    const auto it = object_.find(key);
    if (it == object_.end())
      fail(std::string("missing \"") + key + "\"");
    if (!it->is_number() || !std::isfinite(it->get<double>()))
      fail(std::string("\"") + key + "\" must be a number");
    return it->get<double>();
  }
  double number(const char* key, double fallback) const { return has(key) ? number(key) : fallback; }
  double positive(const char* key) const {
    const double value = number(key);
    if (!(value > 0.0))
      fail(std::string("\"") + key + "\" must be positive");
    return value;
  }
  double positive(const char* key, double fallback) const { return has(key) ? positive(key) : fallback; }
  int count(const char* key) const {
    const double value = number(key);
    if (value < 1 || value > 10000 || value != std::floor(value))
      fail(std::string("\"") + key + "\" must be a whole number from 1");
    return static_cast<int>(value);
  }
  std::string text(const char* key, const std::string& fallback) const {
    const auto it = object_.find(key);
    if (it == object_.end())
      return fallback;
    if (!it->is_string())
      fail(std::string("\"") + key + "\" must be a string");
    return it->get<std::string>();
  }
  template <int N>
  Eigen::Matrix<double, N, 1> vector(const char* key) const {
    const auto it = object_.find(key);
    if (it == object_.end())
      fail(std::string("missing \"") + key + "\"");
    if (!it->is_array() || it->size() != N) {
      fail(std::string("\"") + key + "\" must be an array of " + std::to_string(N) + " numbers");
    }
    Eigen::Matrix<double, N, 1> v;
    for (int k = 0; k < N; ++k) {
      const json& item = (*it)[static_cast<std::size_t>(k)];
      if (!item.is_number() || !std::isfinite(item.get<double>()))
        fail(std::string("\"") + key + "\" must hold numbers");
      v[k] = item.get<double>();
    }
    return v;
  }
  const json& raw() const { return object_; }
  const std::string& where() const { return where_; }

 private:
  const json& object_;
  std::string where_;
};

void add_box(WorldDescription& world, const Fields& f, const std::string& name) {
  BoxShape box{name, {}, {}, 0.0};
  if (f.has("min") || f.has("max")) {  // axis-aligned, by corners: handy for walls and floors
    const Eigen::Vector3d lo = f.vector<3>("min");
    const Eigen::Vector3d hi = f.vector<3>("max");
    if (!((hi - lo).array() > 0.0).all())
      f.fail("\"max\" must exceed \"min\" on every axis");
    box.center = (lo + hi) / 2;
    box.size = hi - lo;
  } else {
    box.center = f.vector<3>("center");
    box.size = f.vector<3>("size");
    if (!(box.size.array() > 0.0).all())
      f.fail("\"size\" must be positive on every axis");
    box.yaw = degrees(f.number("yaw_deg", 0.0));
  }
  world.boxes.push_back(box);
}

void add_ramp(WorldDescription& world, const Fields& f, const std::string& name) {
  RampShape ramp{name,
                 f.vector<2>("center"),
                 f.positive("length"),
                 f.positive("width"),
                 degrees(f.number("yaw_deg", 0.0)),
                 f.number("base_z", 0.0),
                 f.number("height_start"),
                 f.number("height_end")};
  if (std::max(ramp.height_start, ramp.height_end) <= ramp.base_z ||
      std::min(ramp.height_start, ramp.height_end) < ramp.base_z) {
    f.fail("\"height_start\" and \"height_end\" must not be below \"base_z\", and one must be above it");
  }
  world.ramps.push_back(ramp);
}

// Stairs climbing in the yaw direction from `start` (the middle of the bottom step's front edge).
void add_stairs(WorldDescription& world, const Fields& f, const std::string& name) {
  const Eigen::Vector2d start = f.vector<2>("start");
  const double yaw = degrees(f.number("yaw_deg", 0.0));
  const double width = f.positive("width");
  const int steps = f.count("steps");
  const double rise = f.positive("rise");
  const double run = f.positive("run");
  const double base = f.number("base_z", 0.0);
  const Eigen::Vector2d forward(std::cos(yaw), std::sin(yaw));
  for (int k = 0; k < steps; ++k) {
    const double top = base + (k + 1) * rise;
    const Eigen::Vector2d mid = start + forward * (run * (k + 0.5));
    world.boxes.push_back({name + "-step" + std::to_string(k + 1),
                           Eigen::Vector3d(mid.x(), mid.y(), (base + top) / 2),
                           Eigen::Vector3d(run, width, top - base), yaw});
  }
}

void add_tree(WorldDescription& world, const Fields& f) {
  const Eigen::Vector2d at = f.vector<2>("at");
  const double base = f.number("base_z", 0.0);
  const double height = f.positive("height", 5.0);
  const double trunk = f.positive("trunk_radius", 0.15);
  const double crown = f.positive("crown_radius", 1.5);
  world.cylinders.push_back({at, trunk, base, base + height - crown});
  world.spheres.push_back({Eigen::Vector3d(at.x(), at.y(), base + height - crown), crown});
}

HeightField make_terrain(const Fields& f) {
  const Eigen::Vector2d origin = f.vector<2>("origin");
  const double cell = f.positive("cell");
  const double base = f.number("base", 0.0);
  if (f.has("heights")) {  // explicit rows, south to north
    const json& rows = f.raw()["heights"];
    if (!rows.is_array() || rows.size() < 2)
      f.fail("\"heights\" must be an array of at least 2 rows");
    const int ny = static_cast<int>(rows.size());
    const int nx = rows[0].is_array() ? static_cast<int>(rows[0].size()) : 0;
    std::vector<double> heights;
    for (const json& row : rows) {
      if (!row.is_array() || static_cast<int>(row.size()) != nx || nx < 2)
        f.fail("\"heights\" rows must have equal length >= 2");
      for (const json& h : row) {
        if (!h.is_number())
          f.fail("\"heights\" must hold numbers");
        heights.push_back(base + h.get<double>());
      }
    }
    return HeightField(origin, cell, nx, ny, std::move(heights));
  }
  const Eigen::Vector2d size = f.vector<2>("size");
  if (!(size.array() > 0.0).all())
    f.fail("\"size\" must be positive");
  // Counted in double first: a size far larger than the cell overflows int (found by fuzzing, as was a size
  // below one cell, which HeightField refused with an exception this function's callers do not expect).
  const double cells_x = std::round(size.x() / cell);
  const double cells_y = std::round(size.y() / cell);
  if (!(cells_x >= 1.0 && cells_y >= 1.0))
    f.fail("\"size\" must be at least one \"cell\" each way");
  if ((cells_x + 1.0) * (cells_y + 1.0) > 16'000'000.0)
    f.fail("terrain has too many cells; use a larger \"cell\"");
  const int nx = static_cast<int>(cells_x) + 1;
  const int ny = static_cast<int>(cells_y) + 1;
  std::vector<double> heights(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), base);
  // Smooth hills: a raised cosine of the given radius and height (negative height: a hollow).
  if (f.has("hills")) {
    const json& hills = f.raw()["hills"];
    if (!hills.is_array())
      f.fail("\"hills\" must be an array");
    for (std::size_t h = 0; h < hills.size(); ++h) {
      const Fields hill(hills[h], f.where() + ".hills[" + std::to_string(h) + "]");
      const Eigen::Vector2d center = hill.vector<2>("center");
      const double radius = hill.positive("radius");
      const double height = hill.number("height");
      for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
          const double r = (origin + Eigen::Vector2d(i, j) * cell - center).norm();
          if (r < radius)
            heights[static_cast<std::size_t>(j * nx + i)] += height * 0.5 * (1 + std::cos(kPi * r / radius));
        }
      }
    }
  }
  return HeightField(origin, cell, nx, ny, std::move(heights));
}

}  // namespace

WorldDescription parse_world(std::string_view text, std::string_view source) {
  const io::JsonInput input = io::parse_json(text);
  if (!input.ok())
    throw std::runtime_error(std::string(source) + ": " + input.error);
  const json& document = input.value;
  const Fields top(document, std::string(source));
  WorldDescription world;
  world.name = top.text("name", "unnamed");
  world.summary = top.text("summary", "");

  const json spawn_object = top.has("spawn") ? document["spawn"] : json::object();
  const Fields spawn(spawn_object, std::string(source) + ".spawn");
  world.spawn = {spawn.number("x", 0.0), spawn.number("y", 0.0), degrees(spawn.number("yaw_deg", 0.0))};
  world.spawn_z = spawn.number("z", 0.0);

  if (top.has("terrain"))
    world.terrain = make_terrain(Fields(document["terrain"], std::string(source) + ".terrain"));

  const json shapes = top.has("shapes") ? document["shapes"] : json::array();
  if (!shapes.is_array())
    top.fail("\"shapes\" must be an array");
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const Fields f(shapes[k], std::string(source) + ".shapes[" + std::to_string(k) + "]");
    const std::string type = f.text("type", "");
    const std::string name = f.text("name", type + std::to_string(k));
    if (type == "box") {
      add_box(world, f, name);
    } else if (type == "ramp") {
      add_ramp(world, f, name);
    } else if (type == "stairs") {
      add_stairs(world, f, name);
    } else if (type == "cylinder") {
      const double z_min = f.number("z_min", 0.0);
      const double z_max = f.number("z_max");
      if (z_max <= z_min)
        f.fail("\"z_max\" must exceed \"z_min\"");
      world.cylinders.push_back({f.vector<2>("center"), f.positive("radius"), z_min, z_max});
    } else if (type == "sphere") {
      world.spheres.push_back({f.vector<3>("center"), f.positive("radius")});
    } else if (type == "tree") {
      add_tree(world, f);
    } else {
      f.fail("unknown \"type\" \"" + type + "\" (box, ramp, stairs, cylinder, sphere, tree)");
    }
  }

  if (top.has("route")) {
    const json& route = document["route"];
    if (!route.is_array())
      top.fail("\"route\" must be an array of [x, y] points");
    for (std::size_t k = 0; k < route.size(); ++k) {
      const json& point = route[k];
      if (!point.is_array() || point.size() != 2 || !point[0].is_number() || !point[1].is_number()) {
        top.fail("route[" + std::to_string(k) + "] must be [x, y]");
      }
      world.route.emplace_back(point[0].get<double>(), point[1].get<double>());
    }
  }
  if (world.route.size() == 1)
    top.fail("\"route\" needs at least two points (or none)");
  if (world.boxes.empty() && world.ramps.empty() && world.cylinders.empty() && world.spheres.empty() &&
      !world.terrain) {
    top.fail("the world has no shapes and no terrain");
  }
  return world;
}

WorldDescription load_world_file(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream)
    throw std::runtime_error(path.string() + ": cannot open world file");
  std::ostringstream text;
  text << stream.rdbuf();
  return parse_world(text.str(), path.string());
}

std::vector<std::string> builtin_world_names() {
  std::vector<std::string> names;
  for (const auto& entry : embedded_worlds())
    names.emplace_back(entry.name);
  return names;
}

std::string_view builtin_world_text(std::string_view name) {
  for (const auto& entry : embedded_worlds()) {
    if (entry.name == name)
      return entry.text;
  }
  throw std::invalid_argument("no built-in world \"" + std::string(name) + "\"");
}

WorldDescription builtin_world(std::string_view name) {
  return parse_world(builtin_world_text(name), "built-in world " + std::string(name));
}

}  // namespace strata::sim

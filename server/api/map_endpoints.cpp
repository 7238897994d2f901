// REST: the map for download, the occupancy image, tiles with ETags, and saved maps.
#include <spdlog/fmt/fmt.h>

#include <charconv>
#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "server/api/http_router.hpp"
#include "server/api/operator_commands.hpp"
#include "server/api/responses.hpp"
#include "server/auth/request_auth.hpp"
#include "server/protocol/binary_frames.hpp"
#include "server/protocol/client_messages.hpp"

namespace strata::api {
namespace {

namespace http = protocol::http;
using protocol::ErrorCode;

/// FNV-1a, 64 bits: a content fingerprint for ETags (not security; versions alone can repeat after a load).
std::uint64_t fingerprint(const void* data, std::size_t size) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::string tile_etag(const EncodedTile& tile) {
  return fmt::format("\"{}-{:016x}\"", tile.version, fingerprint(tile.draco.data(), tile.draco.size()));
}

std::string_view query_value(std::string_view query, std::string_view name) {
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    if (pair.starts_with(name) && pair.size() > name.size() && pair[name.size()] == '=')
      return pair.substr(name.size() + 1);
    if (amp == std::string_view::npos)
      break;
    query.remove_prefix(amp + 1);
  }
  return {};
}

/// A response that can be answered 304 when the client has it already.
protocol::HttpResponse cacheable(const protocol::HttpRequest& request, std::string body,
                                 std::string_view content_type, const std::string& etag) {
  if (etag_matches(request[http::field::if_none_match], etag)) {
    protocol::HttpResponse response{http::status::not_modified, request.version()};
    response.set(http::field::server, "strata");
    response.set(http::field::etag, etag);
    response.keep_alive(request.keep_alive());
    return response;
  }
  auto response = make_response(request, http::status::ok, std::move(body), content_type);
  response.set(http::field::etag, etag);
  // Caches may keep it but must ask again: tiles change as the robot maps.
  response.set(http::field::cache_control, "no-cache");
  return response;
}

}  // namespace

protocol::HttpResponse HttpRouter::map_download(const protocol::HttpRequest& request,
                                                std::string_view query) const {
  if (services_.maps == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "maps are not available on this server");
  }
  std::string_view format = query_value(query, "format");
  if (format.empty())
    format = "strata";
  struct Kind {
    std::string_view format, content_type, file;
  };
  static constexpr Kind kKinds[] = {{"strata", "application/octet-stream", "map.strata"},
                                    {"ply", "application/octet-stream", "map.ply"},
                                    {"pgm", "image/x-portable-graymap", "map.pgm"},
                                    {"yaml", "application/yaml", "map.yaml"},
                                    {"mcap", "application/octet-stream", "map.mcap"}};
  for (const auto& kind : kKinds) {
    if (kind.format != format)
      continue;
    // MCAP's chunks zstd-compressed (the default) or not: compression=zstd|none.
    std::string download_format(format);
    if (const std::string_view compression = query_value(query, "compression"); !compression.empty()) {
      if (format != "mcap" || (compression != "zstd" && compression != "none")) {
        return error_response(request, http::status::bad_request, ErrorCode::kBadParams,
                              "compression is zstd or none, and only for format=mcap");
      }
      if (compression == "none")
        download_format = "mcap-uncompressed";
    }
    std::optional<std::uint64_t> version;
    if (const std::string_view text = query_value(query, "version"); !text.empty()) {
      std::uint64_t value = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (error != std::errc() || end != text.data() + text.size()) {
        return error_response(request, http::status::bad_request, ErrorCode::kBadParams,
                              "version must be a map version, a whole number (X-Strata-Version)");
      }
      version = value;
    }
    const MapDownload download = services_.maps->download(download_format, version);
    if (download.version_gone) {
      return error_response(request, http::status::gone, ErrorCode::kNotFound,
                            fmt::format("map version {} is gone (the map is at version {}): fetch the YAML "
                                        "again and its image by the version it names",
                                        *version, download.version));
    }
    if (download.bytes.empty()) {
      return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                            "there is no map yet");
    }
    auto response =
        make_response(request, http::status::ok, std::string(download.bytes.begin(), download.bytes.end()),
                      kind.content_type);
    response.set(http::field::content_disposition, fmt::format("attachment; filename=\"{}\"", kind.file));
    response.set(http::field::cache_control, "no-store");
    response.set("X-Strata-Version", std::to_string(download.version));
    response.set("X-Strata-Export", download.reused ? "reused" : "made");
    return response;
  }
  return error_response(request, http::status::bad_request, ErrorCode::kBadParams,
                        "format must be one of strata, ply, pgm, yaml, mcap");
}

protocol::HttpResponse HttpRouter::occupancy(const protocol::HttpRequest& request) const {
  const auto snapshot = services_.map ? services_.map->snapshot() : nullptr;
  if (!snapshot || !snapshot->occupancy) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "there is no drivable map yet");
  }
  const EncodedOccupancy& image = *snapshot->occupancy;
  const std::string etag =
      fmt::format("\"{}-{:016x}\"", image.version, fingerprint(image.png.data(), image.png.size()));
  auto response = cacheable(request, std::string(image.png.begin(), image.png.end()), "image/png", etag);
  // The image's place in the map, as the occupancy frame's header carries it.
  response.set("X-Strata-Origin", fmt::format("{},{}", image.origin_x, image.origin_y));
  response.set("X-Strata-Resolution", fmt::format("{}", image.resolution));
  response.set("X-Strata-Level", fmt::format("{}", image.level_z));
  response.set("X-Strata-Version", std::to_string(image.version));
  return response;
}

protocol::HttpResponse HttpRouter::tile_index(const protocol::HttpRequest& request) const {
  const auto snapshot = services_.map ? services_.map->snapshot() : nullptr;
  nlohmann::json tiles = nlohmann::json::array();
  if (snapshot) {
    for (const auto& tile : snapshot->tiles) {
      tiles.push_back({{"x", tile->tile_x},
                       {"y", tile->tile_y},
                       {"version", tile->version},
                       {"patches", tile->patches},
                       {"bytes", tile->draco.size()},
                       {"etag", tile_etag(*tile)}});
    }
  }
  return json_response(
      request, http::status::ok,
      nlohmann::json{{"version", snapshot ? snapshot->version : 0}, {"tiles", std::move(tiles)}}.dump());
}

protocol::HttpResponse HttpRouter::tile(const protocol::HttpRequest& request,
                                        std::string_view coordinates) const {
  // "{x}/{y}", integers.
  const std::size_t slash = coordinates.find('/');
  int x = 0;
  int y = 0;
  const auto parse = [](std::string_view text, int& value) {
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() && !text.empty();
  };
  if (slash == std::string_view::npos || !parse(coordinates.substr(0, slash), x) ||
      !parse(coordinates.substr(slash + 1), y)) {
    return error_response(request, http::status::not_found, ErrorCode::kNotFound,
                          "tiles are at /api/v1/tiles/{x}/{y} with integer tile indices");
  }
  const auto snapshot = services_.map ? services_.map->snapshot() : nullptr;
  if (snapshot) {
    for (const auto& tile : snapshot->tiles) {
      if (tile->tile_x == x && tile->tile_y == y)
        return cacheable(request, protocol::encode_tile_frame(*tile), "application/vnd.strata.tile",
                         tile_etag(*tile));
    }
  }
  return error_response(request, http::status::not_found, ErrorCode::kNotFound,
                        fmt::format("no tile {},{} in the map", x, y));
}

protocol::HttpResponse HttpRouter::maps(const protocol::HttpRequest& request, std::string_view rest) const {
  // Anyone may see which maps there are (a viewer, too); saving and loading need the operator. A token
  // offered and wrong is refused either way: the page checks a token by listing.
  const bool listing = rest.empty() && is_read(request);
  const auth::AuthOutcome outcome = auth::authenticate(request, services_.network.operator_token);
  if (listing && (outcome == auth::AuthOutcome::kBadToken || outcome == auth::AuthOutcome::kWrongScheme)) {
    return error_response(request, http::status::unauthorized, ErrorCode::kUnauthorized,
                          std::string(auth::refusal_reason(outcome)));
  }
  if (!listing) {
    if (auto refusal = require_operator(request))
      return std::move(*refusal);
  }
  MapCommands* maps = services_.maps;
  if (maps == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "maps are not available on this server");
  }
  if (rest.empty()) {
    if (is_read(request)) {
      nlohmann::json list = nlohmann::json::array();
      for (const auto& file : maps->list_maps())
        list.push_back({{"name", file.name}, {"bytes", file.bytes}, {"modified", file.modified}});
      // A file copied into the maps directory may have a name that is not UTF-8: shown with U+FFFD.
      return json_response(request, http::status::ok,
                           nlohmann::json{{"maps", std::move(list)}}.dump(
                               -1, ' ', false, nlohmann::json::error_handler_t::replace));
    }
    if (request.method() != http::verb::post)
      return method_not_allowed(request, "GET, HEAD, POST");
    // The body is the WebSocket save_map message without "op": {"name": "<file name>"}.
    auto command = command_from_body(request, "save_map");
    if (auto* refusal = std::get_if<protocol::HttpResponse>(&command))
      return std::move(*refusal);
    const auto& save = std::get<protocol::SaveMapRequest>(std::get<protocol::ClientRequest>(command));
    const CommandResult result = run_operator_command(services_, save, std::chrono::steady_clock::now());
    if (!result.ok)
      return command_error(request, result.code, result.message);
    return json_response(request, http::status::created, nlohmann::json{{"name", save.name}}.dump());
  }
  // "/{name}/load"
  constexpr std::string_view kLoad = "/load";
  if (rest.size() > kLoad.size() + 1 && rest.ends_with(kLoad)) {  // "/load" alone names no map
    const std::string name(rest.substr(1, rest.size() - 1 - kLoad.size()));
    if (request.method() != http::verb::post)
      return method_not_allowed(request, "POST");
    if (!protocol::is_valid_map_name(name)) {
      return error_response(
          request, http::status::bad_request, ErrorCode::kBadParams,
          "a map name is 1-64 characters of A-Z a-z 0-9 . _ - and does not start with a dot");
    }
    // The body is the WebSocket load_map message without "op" and "name" (the URL's): empty, or
    // {"mode": "mapping"} (the default) or {"mode": "localize"}.
    auto command = command_from_body(request, "load_map", {{"name", name}});
    if (auto* refusal = std::get_if<protocol::HttpResponse>(&command))
      return std::move(*refusal);
    const auto& load = std::get<protocol::LoadMapRequest>(std::get<protocol::ClientRequest>(command));
    const CommandResult result = run_operator_command(services_, load, std::chrono::steady_clock::now());
    if (!result.ok)
      return command_error(request, result.code, result.message);
    return json_response(
        request, http::status::ok,
        nlohmann::json{{"loaded", name}, {"mode", to_string(load.mode)}, {"message", result.message}}.dump());
  }
  return error_response(request, http::status::not_found, ErrorCode::kNotFound,
                        "saved maps: GET/POST /api/v1/maps, POST /api/v1/maps/{name}/load");
}

}  // namespace strata::api

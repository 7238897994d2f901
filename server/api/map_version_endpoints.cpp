// REST: the map server's immutable map versions (docs/fleet.md, "The map server").
#include <spdlog/fmt/fmt.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server/api/byte_range.hpp"
#include "server/api/http_router.hpp"
#include "server/api/responses.hpp"

namespace strata::api {
namespace {

namespace http = protocol::http;
using protocol::ErrorCode;

/// A version never changes under its URL: any cache may keep it for a year without asking again.
constexpr std::string_view kImmutable = "public, max-age=31536000, immutable";

std::string version_url(const MapVersionInfo& info) {
  return "/api/v1/maps/" + info.name + "/versions/" + info.version;
}

}  // namespace

protocol::HttpResponse HttpRouter::map_version_list(const protocol::HttpRequest& request) const {
  if (services_.maps == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "maps are not available on this server");
  }
  nlohmann::json list = nlohmann::json::array();
  for (const auto& info : services_.maps->list_map_versions()) {
    list.push_back({{"name", info.name},
                    {"version", info.version},
                    {"bytes", info.bytes},
                    {"sha256", info.sha256},
                    {"url", version_url(info)}});
  }
  return json_response(request, http::status::ok, nlohmann::json{{"versions", std::move(list)}}.dump());
}

protocol::HttpResponse HttpRouter::map_version(const protocol::HttpRequest& request, std::string_view name,
                                               std::string_view version) const {
  if (services_.maps == nullptr) {
    return error_response(request, http::status::service_unavailable, ErrorCode::kUnavailable,
                          "maps are not available on this server");
  }
  MapVersionFile file = services_.maps->read_map_version(std::string(name), std::string(version));
  if (!file.result.ok)
    return command_error(request, file.result.code, file.result.message);
  const std::string etag = "\"" + file.info.sha256 + "\"";  // strong: the bytes' own hash
  const auto with_validators = [&](protocol::HttpResponse response) {
    response.set(http::field::etag, etag);
    response.set(http::field::cache_control, kImmutable);
    response.set(http::field::accept_ranges, "bytes");
    return response;
  };
  if (etag_matches(request[http::field::if_none_match], etag)) {
    protocol::HttpResponse response{http::status::not_modified, request.version()};
    response.set(http::field::server, "strata");
    response.keep_alive(request.keep_alive());
    return with_validators(std::move(response));
  }
  const std::uint64_t size = file.bytes.size();
  ByteRange range = parse_byte_range(request[http::field::range], size);
  // If-Range with another validator: the client's part is of other bytes, it gets the whole file.
  if (const auto if_range = request[http::field::if_range]; !if_range.empty() && if_range != etag)
    range = {};
  if (range.kind == ByteRange::Kind::kUnsatisfiable) {
    auto response = error_response(request, http::status::range_not_satisfiable, ErrorCode::kBadRequest,
                                   fmt::format("the range is outside the file's {} bytes", size));
    response.set(http::field::content_range, fmt::format("bytes */{}", size));
    return response;
  }
  if (range.kind == ByteRange::Kind::kPart) {
    auto response = make_response(request, http::status::partial_content,
                                  file.bytes.substr(range.first, range.last - range.first + 1),
                                  "application/octet-stream");
    response.set(http::field::content_range, fmt::format("bytes {}-{}/{}", range.first, range.last, size));
    return with_validators(std::move(response));
  }
  auto response = make_response(request, http::status::ok, std::move(file.bytes), "application/octet-stream");
  response.set(http::field::content_disposition,
               fmt::format("attachment; filename=\"{}-{}.strata\"", file.info.name, file.info.version));
  response.set("X-Strata-Sha256", file.info.sha256);
  return with_validators(std::move(response));
}

}  // namespace strata::api

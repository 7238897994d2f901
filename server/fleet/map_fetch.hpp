#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace strata::fleet {

/// Where a downloadMap's file is: `http://HOST[:PORT]/PATH` or `https://...` (TLS, the host's certificate
/// checked against the system's CAs and its name).
struct HttpUrl {
  bool tls = false;
  std::string host;
  int port = 80;
  std::string target = "/";  ///< path and query
};
[[nodiscard]] std::optional<HttpUrl> parse_http_url(std::string_view url, std::string* error = nullptr);

struct FetchLimits {
  std::size_t max_bytes = 512u << 20;  ///< a larger body is refused while it arrives
  std::chrono::seconds timeout{60};    ///< for the whole fetch: connect, request, response
};

/// The body of a GET of `url` answered 200, or the reason there is none ("HTTP 404 Not Found", "timed
/// out after 60 s", the resolver's or TLS's error). Blocks: run it off the event loop. Redirects are not
/// followed (a map server's URLs are stable).
struct FetchResult {
  std::string body;
  std::string error;  ///< empty: fetched
  [[nodiscard]] bool ok() const { return error.empty(); }
};
[[nodiscard]] FetchResult fetch_url(std::string_view url, const FetchLimits& limits = {});

}  // namespace strata::fleet

#pragma once

#include <string_view>

#include "server/protocol/http_types.hpp"

namespace strata::auth {

/// What every response says to the browser about itself (issue 59 item 12): its content type is what it
/// is (no sniffing a map download into a page), and the web app's pages load scripts, styles, images and
/// connections from this server alone, and are framed by no one (clickjacking a Stop or a goal).
inline void add_security_headers(protocol::HttpResponse& response) {
  namespace http = protocol::http;
  response.set("X-Content-Type-Options", "nosniff");
  if (!std::string_view(response[http::field::content_type]).starts_with("text/html"))
    return;
  // The map's tiles are decoded by Draco's WebAssembly build in workers three.js makes from blob: URLs.
  response.set("Content-Security-Policy",
               "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; worker-src 'self' blob:; "
               "style-src 'self'; img-src 'self' data: blob:; connect-src 'self'; object-src 'none'; "
               "base-uri 'self'; form-action 'self'; frame-ancestors 'none'");
  response.set("X-Frame-Options", "DENY");
  response.set("Referrer-Policy", "no-referrer");
}

}  // namespace strata::auth

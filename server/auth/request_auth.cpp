#include "server/auth/request_auth.hpp"

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>

#include "drivers/io/text_fields.hpp"

namespace strata::auth {
namespace {

using io::trimmed;  // header values: blanks around list items and values do not count

namespace http = protocol::http;

bool iequals(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  });
}

/// The `Authorization` header's value, if there is one.
std::optional<std::string_view> authorization(const protocol::HttpRequest& request) {
  const auto found = request.find(http::field::authorization);
  if (found == request.end())
    return std::nullopt;
  return trimmed(found->value());
}

/// The token of an `Authorization: Bearer <token>` value; none for another scheme.
std::optional<std::string_view> bearer_token(std::string_view value) {
  constexpr std::string_view kScheme = "bearer ";
  if (iequals(value, kScheme.substr(0, kScheme.size() - 1)))
    return std::string_view();  // the scheme with an empty token (the header's blanks are trimmed)
  if (value.size() < kScheme.size() || !iequals(value.substr(0, kScheme.size()), kScheme))
    return std::nullopt;
  return trimmed(value.substr(kScheme.size()));
}

std::optional<std::string_view> subprotocol_token(const protocol::HttpRequest& request) {
  std::string_view offered = request[http::field::sec_websocket_protocol];
  while (!offered.empty()) {
    const std::size_t comma = offered.find(',');
    const std::string_view item = trimmed(offered.substr(0, comma));
    if (item.starts_with(kTokenSubprotocolPrefix))
      return item.substr(kTokenSubprotocolPrefix.size());
    if (comma == std::string_view::npos)
      break;
    offered.remove_prefix(comma + 1);
  }
  return std::nullopt;
}

std::optional<std::string_view> cookie_token(const protocol::HttpRequest& request) {
  for (auto field = request.find(http::field::cookie);
       field != request.end() && field->name() == http::field::cookie; ++field) {
    std::string_view cookies = field->value();
    while (!cookies.empty()) {
      const std::size_t semicolon = cookies.find(';');
      const std::string_view pair = trimmed(cookies.substr(0, semicolon));
      const std::size_t equals = pair.find('=');
      if (equals != std::string_view::npos && pair.substr(0, equals) == kTokenCookie)
        return pair.substr(equals + 1);
      if (semicolon == std::string_view::npos)
        break;
      cookies.remove_prefix(semicolon + 1);
    }
  }
  return std::nullopt;
}

}  // namespace

bool is_same_origin(const protocol::HttpRequest& request) {
  const auto origin = request.find(http::field::origin);
  const auto host = request.find(http::field::host);
  if (origin == request.end() || host == request.end())
    return false;
  std::string_view origin_host = trimmed(origin->value());
  const std::size_t scheme_end = origin_host.find("://");
  if (scheme_end == std::string_view::npos)
    return false;  // "null" (sandboxed frames, file://) never counts as ours
  origin_host.remove_prefix(scheme_end + 3);
  return !origin_host.empty() && iequals(origin_host, trimmed(host->value()));
}

namespace {

/// An Origin as it is compared: without blanks around it and without a trailing '/'.
std::string_view normalized_origin(std::string_view origin) {
  origin = trimmed(origin);
  if (origin.ends_with('/'))
    origin.remove_suffix(1);
  return origin;
}

}  // namespace

bool origin_allowed(const protocol::HttpRequest& request, const std::vector<std::string>& allowed_origins) {
  const auto origin = request.find(http::field::origin);
  if (origin == request.end())
    return true;
  if (is_same_origin(request))
    return true;
  const std::string_view offered = normalized_origin(origin->value());
  return std::any_of(allowed_origins.begin(), allowed_origins.end(), [offered](const std::string& allowed) {
    return allowed == "*" || iequals(normalized_origin(allowed), offered);
  });
}

bool is_valid_origin_pattern(std::string_view origin) {
  origin = normalized_origin(origin);
  if (origin == "*" || origin == "null")
    return true;
  std::size_t host_start = 0;
  if (origin.starts_with("http://"))
    host_start = 7;
  else if (origin.starts_with("https://"))
    host_start = 8;
  else
    return false;
  const std::string_view host = origin.substr(host_start);
  return !host.empty() && std::all_of(host.begin(), host.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '-' || c == ':' || c == '[' ||
           c == ']';
  });
}

std::string_view refusal_reason(AuthOutcome outcome) {
  if (outcome == AuthOutcome::kWrongScheme)
    return "the operator token goes in an Authorization header of the Bearer scheme: Authorization: Bearer "
           "<token>";
  return "the operator token is wrong";
}

AuthOutcome authenticate(const protocol::HttpRequest& request, std::string_view operator_token) {
  const auto check = [operator_token](std::string_view token) {
    return !operator_token.empty() && constant_time_equal(token, operator_token) ? AuthOutcome::kOperator
                                                                                 : AuthOutcome::kBadToken;
  };
  if (const auto header = authorization(request)) {
    // Another scheme is a token offered in a way we do not take: refused, never downgraded to watching.
    const auto token = bearer_token(*header);
    return token ? check(*token) : AuthOutcome::kWrongScheme;
  }
  if (const auto token = subprotocol_token(request))
    return check(*token);
  // A stale cookie (the token changed since) should not lock a page out of watching: it only ever adds.
  if (const auto token = cookie_token(request);
      token && is_same_origin(request) && check(*token) == AuthOutcome::kOperator)
    return AuthOutcome::kOperator;
  return AuthOutcome::kViewer;
}

}  // namespace strata::auth

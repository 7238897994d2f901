#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace strata::auth {

/// The names this machine answers to without configuration: "localhost", its host name (gethostname) and
/// "<host name>.local" (mDNS), lower case.
[[nodiscard]] std::vector<std::string> own_host_names();

/// Whether a request's Host header names this server, against DNS rebinding: a page on evil.example whose
/// name is re-pointed at the robot's address is same-origin with the robot as far as the browser knows,
/// so the Origin check does not stop it; but its requests still say `Host: evil.example`. Allowed: no Host
/// header (HTTP/1.0 scripts; browsers always send one), IP literals (IPv4, IPv6 in brackets) with or
/// without a port, and the names in `allowed_hosts` (own_host_names() plus the allowed-hosts option),
/// case-insensitive, with or without a port; "*" allows any.
[[nodiscard]] bool host_allowed(std::string_view host_header, const std::vector<std::string>& allowed_hosts);

/// Whether `host` can be an entry of allowed-hosts: "*" or a DNS name (letters, digits, '-', '.'), without
/// scheme, port or path.
[[nodiscard]] bool is_valid_host_pattern(std::string_view host);

}  // namespace strata::auth

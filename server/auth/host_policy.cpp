#include "server/auth/host_policy.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/algorithm/string/predicate.hpp>
#include <boost/asio/ip/address.hpp>
#include <cctype>

namespace strata::auth {
namespace {

bool all_digits(std::string_view text) {
  return std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

std::string lower_case(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower;
}

}  // namespace

std::vector<std::string> own_host_names() {
  std::vector<std::string> names{"localhost"};
  std::array<char, 256> buffer{};
  if (gethostname(buffer.data(), buffer.size() - 1) == 0 && buffer[0] != '\0') {
    const std::string name = lower_case(buffer.data());
    names.push_back(name);
    if (!name.ends_with(".local"))
      names.push_back(name + ".local");
  }
  return names;
}

bool host_allowed(std::string_view host_header, const std::vector<std::string>& allowed_hosts) {
  while (!host_header.empty() && (host_header.front() == ' ' || host_header.front() == '\t'))
    host_header.remove_prefix(1);
  while (!host_header.empty() && (host_header.back() == ' ' || host_header.back() == '\t'))
    host_header.remove_suffix(1);
  if (host_header.empty())
    return true;
  if (std::find(allowed_hosts.begin(), allowed_hosts.end(), "*") != allowed_hosts.end())
    return true;
  boost::system::error_code error;
  if (host_header.front() == '[') {
    const std::size_t close = host_header.find(']');
    if (close == std::string_view::npos)
      return false;
    const std::string_view rest = host_header.substr(close + 1);
    if (!rest.empty() && !(rest.front() == ':' && all_digits(rest.substr(1))))
      return false;
    (void)boost::asio::ip::make_address_v6(host_header.substr(1, close - 1), error);
    return !error;
  }
  std::string_view name = host_header;
  if (const std::size_t colon = name.find(':'); colon != std::string_view::npos) {
    if (!all_digits(name.substr(colon + 1)))
      return false;
    name = name.substr(0, colon);
  }
  (void)boost::asio::ip::make_address_v4(name, error);
  if (!error)
    return true;
  if (name.ends_with('.'))  // the fully qualified form of the same name
    name.remove_suffix(1);
  return std::any_of(allowed_hosts.begin(), allowed_hosts.end(),
                     [&](const std::string& allowed) { return boost::algorithm::iequals(allowed, name); });
}

bool is_valid_host_pattern(std::string_view host) {
  if (host == "*")
    return true;
  return !host.empty() && host.size() <= 253 && host.front() != '.' && host.front() != '-' &&
         std::all_of(host.begin(), host.end(),
                     [](unsigned char c) { return std::isalnum(c) != 0 || c == '-' || c == '.'; });
}

}  // namespace strata::auth

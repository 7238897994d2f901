#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace strata::build_info {

[[nodiscard]] std::string version();
/// Versions of the libraries this binary was built against: what a bug report needs.
[[nodiscard]] nlohmann::json libraries();

}  // namespace strata::build_info

#include "server/app/config_file.hpp"

namespace strata::app {

void allow_config_file(CLI::App& app) {
  app.set_config("--config", "", "Read options from this file (INI/TOML; see deploy/strata.example.ini)");
  app.allow_config_extras(CLI::config_extras_mode::error);
}

}  // namespace strata::app

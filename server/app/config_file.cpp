#include "server/app/config_file.hpp"

#include <stdexcept>
#include <string>

namespace strata::app {

void allow_config_file(CLI::App& app) {
  app.set_config("--config", "", "Read options from this file (INI/TOML; see deploy/strata.example.ini)");
  app.allow_config_extras(CLI::config_extras_mode::error);
}

void parse_options(const std::function<void()>& parse) {
  try {
    parse();
  } catch (const std::out_of_range& error) {
    throw CLI::ConversionError(std::string("a value is out of range (") + error.what() + ")");
  } catch (const std::invalid_argument& error) {
    throw CLI::ConversionError(std::string("a value is not a number (") + error.what() + ")");
  }
}

}  // namespace strata::app

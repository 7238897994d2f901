#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace strata::app {

/// Lets every option of `app` and its subcommands also come from a config file: `--config FILE`, INI or TOML,
/// the options by their long names under a section named after their subcommand ([serve],
/// deploy/strata.example.ini). The command line wins. A key no option has is refused (CLI::ConfigError), not
/// ignored: a misspelt `max-client` would otherwise leave the robot on the default without a word.
void allow_config_file(CLI::App& app);

/// Calls `parse` (App::parse of the command line, or App::parse_from_stream of a config file) with every
/// mistake in the options reported as a CLI::ParseError, the error main() explains. CLI11 2.1 lets a flag's
/// number beyond 64 bits through as std::stoll's std::out_of_range (`no-imu-calibration =
/// 2222222222222222222222` in a config file ended the process; found by the config file's fuzz target): it
/// becomes a CLI::ConversionError.
void parse_options(const std::function<void()>& parse);

}  // namespace strata::app

#pragma once

#include <CLI/CLI.hpp>

namespace strata::app {

/// Lets every option of `app` and its subcommands also come from a config file: `--config FILE`, INI or TOML,
/// the options by their long names under a section named after their subcommand ([serve],
/// deploy/strata.example.ini). The command line wins. A key no option has is refused (CLI::ConfigError), not
/// ignored: a misspelt `max-client` would otherwise leave the robot on the default without a word.
void allow_config_file(CLI::App& app);

}  // namespace strata::app

#pragma once

#include <CLI/CLI.hpp>

#include "server/app/serve.hpp"

namespace strata::app {

/// Adds `strata serve [options]` to `app`, filling `options`; every option can also come from a config file
/// (`--config FILE`, the long names under [serve], deploy/strata.example.ini).
CLI::App* add_serve_command(CLI::App& app, ServeOptions& options);

}  // namespace strata::app

// strata: the map server's command line. Each subcommand is one job a user or a script runs.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "server/app/config_file.hpp"
#include "server/app/map_command.hpp"
#include "server/app/memory_policy.hpp"
#include "server/app/plan_command.hpp"
#include "server/app/register_command.hpp"
#include "server/app/serve_command.hpp"
#include "server/protocol/build_info.hpp"

namespace {

int parse_failed(const CLI::App& app, const CLI::ParseError& error) {
  if (dynamic_cast<const CLI::ConfigError*>(&error) == nullptr)
    return app.exit(error);
  // CLI11 says "INI was not able to parse serve.max-client"; say what that means and where to look.
  std::cerr << "strata: config file: " << error.what()
            << " (no option of that name; the keys are the long options of `strata serve --help`, under "
               "[serve])\n";
  return error.get_exit_code();
}

int print_version() {
  std::printf("strata %s\n%s\n", strata::build_info::version().c_str(),
              strata::build_info::libraries().dump(2).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool freed_memory_kept = strata::app::keep_freed_memory();  // before any thread starts
  CLI::App app{
      "Strata: a map server for mobile robots on uneven, multi-level ground.\n"
      "Registers 3D scans, builds a Multi-Level Surface map, plans and drives to goals, and serves\n"
      "it all to a browser and to scripts over HTTP and WebSocket.",
      "strata"};
  app.require_subcommand(1);
  app.set_version_flag("--version", strata::build_info::version());
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "Log verbosity: trace, debug, info, warn, error, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));

  strata::app::ServeOptions serve_options;
  auto* serve_cmd = strata::app::add_serve_command(app, serve_options);
  // Every serve option can also come from a config file: `strata serve --config strata.ini`.
  strata::app::allow_config_file(app);

  strata::app::RegisterOptions register_options;
  auto* register_cmd = strata::app::add_register_command(app, register_options);

  strata::app::MapBuildOptions map_build;
  strata::app::MapExportOptions map_export;
  const strata::app::MapCommand map_cmd = strata::app::add_map_command(app, map_build, map_export);
  strata::app::PlanOptions plan_options;
  auto* plan_cmd = strata::app::add_plan_command(app, plan_options);

  auto* version_cmd =
      app.add_subcommand("version", "Print the version and the libraries Strata was built with");

  try {
    strata::app::parse_options([&] { app.parse(argc, argv); });
  } catch (const CLI::ParseError& error) {
    return parse_failed(app, error);
  }
  // Logs go to stderr; stdout carries only what scripts read (the "serving on" line, command output).
  spdlog::set_default_logger(spdlog::stderr_color_mt("strata"));
  spdlog::set_level(spdlog::level::from_str(log_level));
  if (!freed_memory_kept)
    spdlog::debug("the C library's allocator keeps its own settings (not glibc, or a sanitizer's)");

  try {
    if (*serve_cmd)
      return strata::app::run_serve(serve_options);
    if (*register_cmd)
      return strata::app::run_register(register_options);
    if (*map_cmd.build)
      return strata::app::run_map_build(map_build);
    if (*map_cmd.export_)
      return strata::app::run_map_export(map_export);
    if (*plan_cmd)
      return strata::app::run_plan(plan_options);
    if (*version_cmd)
      return print_version();
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return 1;
  }
  return 0;
}

// `strata serve` configuration: the config file and the robot parameters, through the real binary.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

TEST(ServeConfig, TheConfigFileSetsOptions) {
  const auto file =
      std::filesystem::temp_directory_path() / ("strata-config-" + std::to_string(::getpid()) + ".ini");
  {
    std::ofstream out(file);
    out << "[serve]\nworld = \"yard\"\nscanner = \"none\"\nrobot-radius = 0.3\nmax-slope = 10\n";
  }
  ServerProcess server({"--config", file.string()});
  const auto world = nlohmann::json::parse(http_get(server.port(), "/api/v1/sim/world").body());
  EXPECT_EQ(world["name"], "yard");
  std::filesystem::remove(file);
}

TEST(ServeConfig, TheSecurityKeysComeFromTheConfigFile) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("strata-config-security-" + std::to_string(::getpid()) + ".ini");
  {
    std::ofstream out(file);
    out << "[serve]\nscanner = \"none\"\nmax-clients = 1\nmax-http-connections = 8\n"
           "allowed-origins = [\"https://kiosk.example\", \"http://panel.example:3000\"]\n"
           "allowed-hosts = [\"robot.example\"]\n";
  }
  ServerProcess server({"--config", file.string()});
  std::filesystem::remove(file);
  WsClient panel(server.port(), "strata.v1", "/ws", {}, "http://panel.example:3000");
  EXPECT_EQ(panel.read()["op"], "hello");
  // max-clients = 1: the second is refused; and a page from an origin not listed is refused as such.
  EXPECT_EQ(websocket_upgrade(server.port(), {}).result(), http::status::service_unavailable);
  EXPECT_EQ(websocket_upgrade(server.port(), {{http::field::origin, "https://elsewhere.example"}}).result(),
            http::status::forbidden);
  // allowed-hosts: the robot's DNS name is served, another name is refused (DNS rebinding).
  EXPECT_EQ(http_get_for_host(server.port(), "/api/v1/pose", "robot.example").result(), http::status::ok);
  EXPECT_EQ(http_get_for_host(server.port(), "/api/v1/pose", "evil.example").result(),
            http::status::forbidden);
}

TEST(ServeConfig, BadRobotParametersAreRefusedAtStart) {
  for (const char* option : {"--robot-radius", "--robot-height", "--max-step", "--max-slope"}) {
    const auto result = run_strata({"serve", "--port", "0", option, "-1"});
    EXPECT_NE(result.exit_code, 0) << option;
    EXPECT_NE(result.output.find(option), std::string::npos) << result.output;
  }
  const auto token = run_strata({"serve", "--port", "0", "--operator-token", "short"});
  EXPECT_NE(token.exit_code, 0);
  EXPECT_NE(token.output.find("operator token"), std::string::npos) << token.output;
}

TEST(ServeConfig, AKeyNoOptionHasIsRefusedAtStart) {
  // A misspelt key (max-client for max-clients) must not leave the robot on the default without a word.
  const auto file =
      std::filesystem::temp_directory_path() / ("strata-config-typo-" + std::to_string(::getpid()) + ".ini");
  {
    std::ofstream out(file);
    out << "[serve]\nscanner = \"none\"\nmax-client = 4\n";
  }
  const auto result = run_strata({"serve", "--port", "0", "--config", file.string()});
  std::filesystem::remove(file);
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("max-client"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("config file"), std::string::npos) << result.output;
}

// The files we ship (the package's /etc/strata/strata.ini and the commented example) start the server as
// they are; only what names this machine's paths is overridden on the command line.
TEST(ServeConfig, TheShippedConfigFilesStartTheServer) {
  const auto scratch =
      std::filesystem::temp_directory_path() / ("strata-config-shipped-" + std::to_string(::getpid()));
  std::filesystem::create_directories(scratch);
  { std::ofstream(scratch / "operator-token") << kTestOperatorToken << "\n"; }
  for (const char* name : {"strata.ini", "strata.example.ini"}) {
    SCOPED_TRACE(name);
    ServerProcess server({"--config", std::string(STRATA_DEPLOY_DIR) + "/" + name, "--maps-dir",
                          (scratch / "maps").string(), "--operator-token-file",
                          (scratch / "operator-token").string(), "--imu-calibration",
                          (scratch / "imu-calibration.json").string(), "--scanner", "none"});
    const auto world = nlohmann::json::parse(http_get(server.port(), "/api/v1/sim/world").body());
    EXPECT_EQ(world["name"], "campus");
  }
  std::filesystem::remove_all(scratch);
}

// Every key the shipped files set or show commented out is an option of `strata serve`, so uncommenting
// one never stops the service.
TEST(ServeConfig, EveryKeyInTheShippedConfigFilesIsAServeOption) {
  const auto help = run_strata({"serve", "--help"});
  ASSERT_EQ(help.exit_code, 0) << help.output;
  const std::regex key_line(R"(^(?:; )?([a-z][a-z0-9-]*) = )");
  for (const char* name : {"strata.ini", "strata.example.ini"}) {
    std::ifstream in(std::string(STRATA_DEPLOY_DIR) + "/" + name);
    ASSERT_TRUE(in) << name;
    int keys = 0;
    for (std::string line; std::getline(in, line);) {
      std::smatch match;
      if (!std::regex_search(line, match, key_line))
        continue;
      ++keys;
      EXPECT_NE(help.output.find("--" + match[1].str()), std::string::npos) << name << ": " << line;
    }
    EXPECT_GT(keys, 5) << name;
  }
}

}  // namespace
}  // namespace strata::testing

// TLS (`serve --tls-cert FILE --tls-key FILE`): a self-signed certificate made at test time with the
// openssl CLI, the real server started with it, real clients over TLS (https://, wss://) and in the clear.
#include <gtest/gtest.h>
#include <openssl/ssl.h>
#include <unistd.h>

#include <boost/asio/ssl.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "integration/clients.hpp"
#include "integration/server_process.hpp"

namespace strata::testing {
namespace {

namespace fs = std::filesystem;

/// A directory of this test process's own, removed at the end.
class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("strata-tls-test-" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

struct Certificate {
  fs::path certificate;
  fs::path key;
};

/// A self-signed certificate for 127.0.0.1 (P-256 key, one day) in `dir`, made by the openssl CLI.
Certificate make_self_signed(const fs::path& dir, const std::string& name) {
  Certificate made{dir / (name + ".crt"), dir / (name + ".key")};
  const std::string command =
      "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 1 -subj /CN=127.0.0.1"
      " -addext subjectAltName=IP:127.0.0.1 -keyout '" +
      made.key.string() + "' -out '" + made.certificate.string() + "' 2>/dev/null";
  if (std::system(command.c_str()) != 0 || !fs::exists(made.certificate) || !fs::exists(made.key))
    throw std::runtime_error("openssl could not make a self-signed certificate: " + command);
  return made;
}

/// One server with TLS for the suite (starting one takes a moment), and clients' trust in its certificate.
class Tls : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    certificate_ = make_self_signed(dir_->path(), "server");
    server_ = std::make_unique<ServerProcess>(std::vector<std::string>{
        "--tls-cert", certificate_.certificate.string(), "--tls-key", certificate_.key.string()});
    trust_ = trusting(certificate_.certificate.string());
  }
  static void TearDownTestSuite() {
    trust_.reset();
    server_.reset();
    dir_.reset();
  }
  static std::uint16_t port() { return server_->port(); }

  static inline std::unique_ptr<TempDir> dir_;
  static inline Certificate certificate_;
  static inline std::unique_ptr<ServerProcess> server_;
  static inline std::shared_ptr<ssl::context> trust_;
};

TEST_F(Tls, TheServerAnnouncesAnHttpsUrl) {
  EXPECT_EQ(server_->scheme(), "https");
}

TEST_F(Tls, HttpsServesTheApi) {
  const auto response = https_request(*trust_, port(), http::verb::get, "/api/v1/info");
  ASSERT_EQ(response.result(), http::status::ok) << response.body();
  const auto info = nlohmann::json::parse(response.body());
  expect_schema("rest", "info", info);
  EXPECT_EQ(info["name"], "strata");
}

TEST_F(Tls, TheServerPresentsTheConfiguredCertificate) {
  // A client that trusts only another certificate refuses the handshake.
  const Certificate other = make_self_signed(dir_->path(), "other");
  const auto other_trust = trusting(other.certificate.string());
  EXPECT_THROW(https_request(*other_trust, port(), http::verb::get, "/api/v1/info"), beast::system_error);
}

TEST_F(Tls, Tls12WithACbcSha1SuiteIsRefused) {
  // Issue 59 item 12: TLS 1.2 offered CBC suites with SHA-1 MACs.
  ssl::context old_client(ssl::context::tls_client);
  old_client.load_verify_file(certificate_.certificate.string());
  old_client.set_verify_mode(ssl::verify_peer);
  SSL_CTX_set_max_proto_version(old_client.native_handle(), TLS1_2_VERSION);
  ASSERT_EQ(SSL_CTX_set_cipher_list(old_client.native_handle(), "ECDHE-RSA-AES128-SHA:AES128-SHA"), 1);
  EXPECT_THROW(https_request(old_client, port(), http::verb::get, "/healthz"), beast::system_error);
  // TLS 1.2 with an AEAD suite is served.
  ssl::context tls12(ssl::context::tls_client);
  tls12.load_verify_file(certificate_.certificate.string());
  tls12.set_verify_mode(ssl::verify_peer);
  SSL_CTX_set_max_proto_version(tls12.native_handle(), TLS1_2_VERSION);
  EXPECT_EQ(https_request(tls12, port(), http::verb::get, "/healthz").result(), http::status::ok);
}

TEST_F(Tls, WssOperatorGetsTheLateJoinerStateAndIsServed) {
  const auto client = WssClient::operator_client(*trust_, port(), kTestOperatorToken);
  EXPECT_EQ(client->handshake_response()[http::field::sec_websocket_protocol], "strata.v1");
  // The late joiner's state, in PROTOCOL.md's order: hello (with the operator role), sim_world, status.
  const auto hello = client->read();
  EXPECT_EQ(hello["op"], "hello");
  EXPECT_EQ(hello["role"], "operator");
  EXPECT_EQ(client->read()["op"], "sim_world");
  EXPECT_EQ(client->read()["op"], "status");
  // And the connection carries requests both ways.
  client->send_text(R"({"op":"ping","id":7})");
  EXPECT_EQ(client->read_op("pong")["id"], 7);
}

TEST_F(Tls, AWrongTokenOverWssIsRefused) {
  EXPECT_THROW(WssClient(*trust_, port(), "strata.v1, strata.token.not-the-right-token"),
               beast::system_error);
}

TEST_F(Tls, PlainHttpIsRefusedNotServed) {
  const auto response = http_get(port(), "/api/v1/info");
  EXPECT_EQ(response.result(), http::status::bad_request);
  const auto body = nlohmann::json::parse(response.body());
  expect_schema("rest", "error", body);
  EXPECT_NE(body.dump().find("https://"), std::string::npos) << body.dump();
  EXPECT_FALSE(body.contains("name")) << "the API answered in the clear: " << body.dump();
  // The operator's request is not carried out either, and no plain WebSocket is opened.
  const auto goal =
      http_request(port(), http::verb::post, "/api/v1/goal", R"({"x":1,"y":1})", kTestOperatorToken);
  EXPECT_EQ(goal.result(), http::status::bad_request);
  EXPECT_THROW(WsClient(port(), "strata.v1"), beast::system_error);
  // The server still serves TLS afterwards.
  EXPECT_EQ(https_request(*trust_, port(), http::verb::get, "/healthz").result(), http::status::ok);
}

TEST(TlsConfig, TheConfigFileTurnsTlsOn) {
  const TempDir dir;
  const Certificate certificate = make_self_signed(dir.path(), "server");
  const fs::path config = dir.path() / "strata.ini";
  std::ofstream(config) << "[serve]\ntls-cert = \"" << certificate.certificate.string() << "\"\ntls-key = \""
                        << certificate.key.string() << "\"\n";
  ServerProcess server({"--config", config.string()});
  EXPECT_EQ(server.scheme(), "https");
  const auto trust = trusting(certificate.certificate.string());
  EXPECT_EQ(https_request(*trust, server.port(), http::verb::get, "/api/v1/info").result(), http::status::ok);
  EXPECT_EQ(server.stop(), 0) << "SIGTERM ends the server cleanly (under ASan: without a memory error)";
}

TEST(TlsConfig, BadCertificateOrKeyFilesStopTheServerWithAClearError) {
  const TempDir dir;
  const Certificate good = make_self_signed(dir.path(), "good");
  const Certificate other = make_self_signed(dir.path(), "other");
  const fs::path garbage = dir.path() / "garbage.key";
  std::ofstream(garbage) << "this is not a key\n";

  const auto not_a_key = run_strata(
      {"serve", "--port", "0", "--tls-cert", good.certificate.string(), "--tls-key", garbage.string()});
  EXPECT_NE(not_a_key.exit_code, 0);
  EXPECT_NE(not_a_key.output.find("TLS key file " + garbage.string()), std::string::npos) << not_a_key.output;
  EXPECT_EQ(not_a_key.output.find("serving on"), std::string::npos) << not_a_key.output;

  const auto wrong_key = run_strata(
      {"serve", "--port", "0", "--tls-cert", good.certificate.string(), "--tls-key", other.key.string()});
  EXPECT_NE(wrong_key.exit_code, 0);
  EXPECT_NE(wrong_key.output.find("does not belong to the certificate"), std::string::npos)
      << wrong_key.output;

  const auto key_as_certificate =
      run_strata({"serve", "--port", "0", "--tls-cert", good.key.string(), "--tls-key", good.key.string()});
  EXPECT_NE(key_as_certificate.exit_code, 0);
  EXPECT_NE(key_as_certificate.output.find("TLS certificate file"), std::string::npos)
      << key_as_certificate.output;

  const auto missing = run_strata({"serve", "--port", "0", "--tls-cert", good.certificate.string(),
                                   "--tls-key", (dir.path() / "missing.key").string()});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("missing.key"), std::string::npos) << missing.output;

  const auto half = run_strata({"serve", "--port", "0", "--tls-cert", good.certificate.string()});
  EXPECT_NE(half.exit_code, 0);
  EXPECT_NE(half.output.find("--tls-key"), std::string::npos) << half.output;
}

}  // namespace
}  // namespace strata::testing

#include "server/net/tls_context.hpp"

#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509err.h>

#include <boost/asio/ssl/error.hpp>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace strata::net {
namespace {

namespace ssl = boost::asio::ssl;

// OpenSSL's reasons for a failure, e.g. "PEM lib; no start line" for a file that is not PEM. Asio takes
// the oldest entry of OpenSSL's error queue into `error`; the rest are still queued (and are emptied
// here). `mismatch`: one of them says that the key is not the certificate's.
std::string openssl_reasons(const boost::system::error_code& error, bool* mismatch = nullptr) {
  std::vector<unsigned long> codes;
  if (error && error.category() == boost::asio::error::get_ssl_category())
    codes.push_back(static_cast<unsigned long>(error.value()));
  while (const unsigned long code = ERR_get_error())
    codes.push_back(code);
  std::string reasons;
  for (const unsigned long code : codes) {
    if (mismatch != nullptr && ERR_GET_LIB(code) == ERR_LIB_X509 &&
        ERR_GET_REASON(code) == X509_R_KEY_VALUES_MISMATCH)
      *mismatch = true;
    const char* text = ERR_reason_error_string(code);
    if (text != nullptr && reasons.find(text) == std::string::npos)
      reasons += (reasons.empty() ? "" : "; ") + std::string(text);
  }
  if (reasons.empty())
    reasons = error ? error.message() : "unknown OpenSSL error";
  return reasons;
}

void require_readable(const std::filesystem::path& path, const char* what) {
  std::ifstream file(path);
  if (!file)
    throw std::runtime_error(std::string("cannot read the TLS ") + what + " file " + path.string());
}

}  // namespace

std::shared_ptr<ssl::context> make_tls_context(const std::filesystem::path& certificate_file,
                                               const std::filesystem::path& key_file) {
  require_readable(certificate_file, "certificate");
  require_readable(key_file, "key");
  auto context = std::make_shared<ssl::context>(ssl::context::tls_server);
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                       ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
  // TLS 1.2 with forward secrecy and AEAD only (Mozilla's "intermediate" list): no CBC suites with SHA-1
  // MACs, no static RSA key exchange. TLS 1.3's suites are all of that kind already.
  if (SSL_CTX_set_cipher_list(context->native_handle(),
                              "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-RSA-AES128-GCM-SHA256:"
                              "ECDHE-ECDSA-AES256-GCM-SHA384:ECDHE-RSA-AES256-GCM-SHA384:"
                              "ECDHE-ECDSA-CHACHA20-POLY1305:ECDHE-RSA-CHACHA20-POLY1305") != 1)
    throw std::runtime_error("TLS: OpenSSL refused the cipher list");
  // An encrypted key would make OpenSSL ask for its passphrase on the terminal: refuse it instead.
  context->set_password_callback([](std::size_t, ssl::context::password_purpose) { return std::string(); });
  boost::system::error_code error;
  ERR_clear_error();
  context->use_certificate_chain_file(certificate_file.string(), error);
  if (error) {
    throw std::runtime_error("the TLS certificate file " + certificate_file.string() +
                             " is not a PEM certificate: " + openssl_reasons(error));
  }
  context->use_private_key_file(key_file.string(), ssl::context::pem, error);
  bool mismatch = false;
  if (error) {
    const std::string reasons = openssl_reasons(error, &mismatch);
    if (!mismatch) {
      throw std::runtime_error("the TLS key file " + key_file.string() +
                               " is not an unencrypted PEM private key: " + reasons);
    }
  }
  if (mismatch || SSL_CTX_check_private_key(context->native_handle()) != 1) {
    ERR_clear_error();
    throw std::runtime_error("the TLS key file " + key_file.string() +
                             " does not belong to the certificate " + certificate_file.string());
  }
  return context;
}

}  // namespace strata::net

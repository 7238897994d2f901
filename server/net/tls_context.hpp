#pragma once

#include <boost/asio/ssl/context.hpp>
#include <filesystem>
#include <memory>

namespace strata::net {

/// The server's TLS context from a PEM certificate (chain) file and a PEM private key file: TLS 1.2 or
/// newer only. Throws std::runtime_error naming the file and OpenSSL's reason when a file is missing or
/// unreadable, is not PEM, or the key does not belong to the certificate, so a bad configuration stops
/// the server at start, not at the first client.
[[nodiscard]] std::shared_ptr<boost::asio::ssl::context> make_tls_context(
    const std::filesystem::path& certificate_file, const std::filesystem::path& key_file);

}  // namespace strata::net

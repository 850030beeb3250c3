#include "server/transport/tls_context.h"

#include <openssl/ssl.h>

#include <stdexcept>
#include <string>

namespace sweepd::server {
namespace {

// Mozilla's "intermediate" TLS 1.2 list: forward secrecy and AEAD only.
constexpr const char* kTls12Ciphers =
    "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-RSA-AES128-GCM-SHA256:ECDHE-ECDSA-AES256-GCM-SHA384:"
    "ECDHE-RSA-AES256-GCM-SHA384:ECDHE-ECDSA-CHACHA20-POLY1305:ECDHE-RSA-CHACHA20-POLY1305";

// Runs one loading step; a failure names the flag, the file and OpenSSL's reason.
template <typename Step>
void load(const char* flag, const std::filesystem::path& file, const char* what, Step step) {
  try {
    step();
  } catch (const std::system_error& error) {
    throw std::runtime_error(std::string(flag) + " " + file.string() + ": cannot use it as " +
                             what + " (" + error.code().message() + ")");
  }
}

}  // namespace

asio::ssl::context server_tls_context(const ServerConfig& config) {
  asio::ssl::context context(asio::ssl::context::tls_server);
  SSL_CTX* native = context.native_handle();
  SSL_CTX_set_min_proto_version(native, TLS1_2_VERSION);
  SSL_CTX_set_options(native, SSL_OP_NO_RENEGOTIATION | SSL_OP_NO_COMPRESSION);
  if (SSL_CTX_set_cipher_list(native, kTls12Ciphers) != 1) {
    throw std::runtime_error("TLS: OpenSSL refused the TLS 1.2 cipher list");
  }
  load("--tls-cert", config.tls_cert, "a PEM certificate chain",
       [&] { context.use_certificate_chain_file(config.tls_cert.string()); });
  load("--tls-key", config.tls_key, "the PEM private key of --tls-cert",
       [&] { context.use_private_key_file(config.tls_key.string(), asio::ssl::context::pem); });
  if (!config.tls_client_ca.empty()) {
    load("--tls-client-ca", config.tls_client_ca, "PEM CA certificates", [&] {
      context.load_verify_file(config.tls_client_ca.string());
      // Tell clients which CA to pick their certificate for.
      STACK_OF(X509_NAME)* names = SSL_load_client_CA_file(config.tls_client_ca.c_str());
      if (names == nullptr) throw std::system_error(asio::error::invalid_argument);
      SSL_CTX_set_client_CA_list(native, names);
    });
    context.set_verify_mode(asio::ssl::verify_peer | asio::ssl::verify_fail_if_no_peer_cert);
  }
  return context;
}

}  // namespace sweepd::server

// server_tls_context: the TLS settings of sweepd's TCP listener (Asio's ssl::context over
// Debian's OpenSSL), from --tls-cert, --tls-key and --tls-client-ca.
//
// Input: config.tls_cert (PEM certificate chain, server certificate first), config.tls_key
// (its PEM private key), config.tls_client_ca (PEM CA certificates; empty: no client
// certificate asked for).
// Output: a server context: TLS 1.2 at least (1.3 preferred: OpenSSL negotiates the highest
// both sides have), TLS 1.2 ciphers restricted to forward-secret AEAD suites (ECDHE with
// AES-GCM or ChaCha20-Poly1305; TLS 1.3's own suites are all AEAD), no renegotiation, no
// compression. With a client CA, a client must present a certificate that chains to it, or the
// handshake fails. Throws std::runtime_error naming the flag, the file and OpenSSL's reason
// (unreadable file, not PEM, a key that does not match the certificate).
#pragma once

#include <asio/ssl/context.hpp>

#include "server/config.h"

namespace sweepd::server {

asio::ssl::context server_tls_context(const ServerConfig& config);

}  // namespace sweepd::server

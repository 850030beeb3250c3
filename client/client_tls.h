// ClientTls: how a C++ client reaches sweepd's TCP port — TLS or plain — as the command-line
// flags of every client set it (client/client_tls_flags.h) and client::Connection uses it.
//   enabled          TLS (sweepd started with --tls-cert/--tls-key); the server's certificate
//                    must chain to ca_file and name the host connected to (DNS name or IP
//                    address in its subjectAltName)
//   ca_file          PEM CA certificates to trust; empty: the system's trust store
//   cert_file, key_file  a client certificate and its key (PEM), for a sweepd started with
//                    --tls-client-ca; both or neither
//   allow_plaintext  send a token over plain TCP to a host that is not loopback; without it
//                    client::Connection::hello refuses to (the token would cross the network
//                    in clear)
//   handshake_timeout  how long the TLS handshake may wait for the server's next bytes (a
//                    server that accepts and never answers); zero: for ever
#pragma once

#include <chrono>
#include <string>

namespace sweepd::client {

struct ClientTls {
  bool enabled = false;
  std::string ca_file;
  std::string cert_file;
  std::string key_file;
  bool allow_plaintext = false;
  std::chrono::milliseconds handshake_timeout{30000};
};

}  // namespace sweepd::client

// add_client_tls_flags: the TLS flags every C++ client declares the same way (sweepctl
// --server, stream_poses, render_frames, server_bench), into a ClientTls (client/client_tls.h):
//   --tls                 connect with TLS
//   --tls-ca FILE         PEM CA certificates to trust instead of the system's (implies --tls)
//   --tls-cert FILE       client certificate (PEM; needs --tls-key; implies --tls)
//   --tls-key FILE        its private key (PEM; needs --tls-cert)
//   --allow-plaintext     send the token over plain TCP to a host that is not loopback
// `needs` (optional): an option the flags need, e.g. sweepctl's --server.
#pragma once

#include <CLI/CLI.hpp>

#include "client/client_tls.h"

namespace sweepd::client {

void add_client_tls_flags(CLI::App& app, ClientTls& tls, CLI::Option* needs = nullptr);

}  // namespace sweepd::client

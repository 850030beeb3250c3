#include "client/client_tls_flags.h"

namespace sweepd::client {

void add_client_tls_flags(CLI::App& app, ClientTls& tls, CLI::Option* needs) {
  const auto turns_tls_on = [&tls](const std::string&) { tls.enabled = true; };
  CLI::Option* flags[] = {
      app.add_flag("--tls", tls.enabled, "connect with TLS (sweepd's --tls-cert/--tls-key)"),
      app.add_option("--tls-ca", tls.ca_file,
                     "PEM CA certificates to trust instead of the system's (implies --tls)")
          ->type_name("FILE")
          ->check(CLI::ExistingFile)
          ->each(turns_tls_on),
      app.add_option("--tls-cert", tls.cert_file,
                     "client certificate, PEM, for sweepd's --tls-client-ca (implies --tls)")
          ->type_name("FILE")
          ->check(CLI::ExistingFile)
          ->each(turns_tls_on),
      app.add_option("--tls-key", tls.key_file, "the client certificate's private key, PEM")
          ->type_name("FILE")
          ->check(CLI::ExistingFile),
      app.add_flag("--allow-plaintext", tls.allow_plaintext,
                   "send the token over plain TCP to a host that is not loopback"),
  };
  flags[2]->needs(flags[3]);
  flags[3]->needs(flags[2]);
  if (needs != nullptr) {
    for (CLI::Option* flag : flags) flag->needs(needs);
  }
}

}  // namespace sweepd::client

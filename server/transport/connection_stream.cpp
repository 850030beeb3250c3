#include "server/transport/connection_stream.h"

#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <memory>

namespace sweepd::server {

TlsSession ConnectionStream::tls_session() {
  if (!tls_) return {};
  SSL* ssl = tls_->native_handle();
  TlsSession session{SSL_get_version(ssl), SSL_get_cipher_name(ssl), ""};
  const std::unique_ptr<X509, decltype(&X509_free)> peer(SSL_get1_peer_certificate(ssl), X509_free);
  if (peer) {
    char subject[256];
    X509_NAME_oneline(X509_get_subject_name(peer.get()), subject, sizeof(subject));
    session.client_subject = subject;
  }
  return session;
}

void ConnectionStream::close() {
  std::error_code ignored;
  socket().shutdown(asio::socket_base::shutdown_both, ignored);
  socket().close(ignored);
}

}  // namespace sweepd::server

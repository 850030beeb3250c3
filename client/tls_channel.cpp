#include "client/tls_channel.h"

#include <fcntl.h>
#include <openssl/err.h>
#include <openssl/x509v3.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <asio/ip/address.hpp>
#include <stdexcept>

namespace sweepd::client {
namespace {

constexpr std::size_t kMostPerCall = 1u << 30;  // SSL_read/SSL_write take an int

// OpenSSL's last error on this thread ("certificate verify failed"), or `fallback`.
std::string openssl_reason(const char* fallback) {
  const unsigned long code = ERR_peek_last_error();
  if (code == 0) return fallback;
  const char* reason = ERR_reason_error_string(code);
  return reason != nullptr ? reason : fallback;
}

// SIGPIPE blocked while OpenSSL writes to the socket; one it raised is discarded.
class NoSigpipe {
 public:
  NoSigpipe() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_, &previous_);
  }
  ~NoSigpipe() {
    sigset_t pending;
    sigpending(&pending);
    if (sigismember(&pending, SIGPIPE) == 1 && sigismember(&previous_, SIGPIPE) == 0) {
      const timespec now{0, 0};
      sigtimedwait(&pipe_, nullptr, &now);
    }
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }

 private:
  sigset_t pipe_, previous_;
};

void load(bool ok, const std::string& flag, const std::string& file, const char* what) {
  if (!ok) {
    throw std::runtime_error(flag + " " + file + ": cannot use it as " + what + " (" +
                             openssl_reason("unreadable") + ")");
  }
}

}  // namespace

TlsChannel::TlsChannel(int fd, const std::string& host, const std::string& address,
                       const ClientTls& tls)
    : fd_(fd), address_(address), context_(SSL_CTX_new(TLS_client_method()), SSL_CTX_free) {
  if (!context_) throw std::runtime_error("TLS: OpenSSL could not make a context");
  SSL_CTX* context = context_.get();
  SSL_CTX_set_min_proto_version(context, TLS1_2_VERSION);
  // A reply spans many 16 KiB records: read what the socket holds in one call, not 5-byte
  // header and body apart, record by record.
  SSL_CTX_set_read_ahead(context, 1);
  if (tls.ca_file.empty()) {
    SSL_CTX_set_default_verify_paths(context);
  } else {
    load(SSL_CTX_load_verify_locations(context, tls.ca_file.c_str(), nullptr) == 1, "--tls-ca",
         tls.ca_file, "PEM CA certificates");
  }
  if (!tls.cert_file.empty()) {
    load(SSL_CTX_use_certificate_chain_file(context, tls.cert_file.c_str()) == 1, "--tls-cert",
         tls.cert_file, "a PEM certificate chain");
    load(SSL_CTX_use_PrivateKey_file(context, tls.key_file.c_str(), SSL_FILETYPE_PEM) == 1,
         "--tls-key", tls.key_file, "the PEM private key of --tls-cert");
  }
  SSL_CTX_set_verify(context, SSL_VERIFY_PEER, nullptr);
  ssl_.reset(SSL_new(context));
  SSL* ssl = ssl_.get();
  // The certificate must name what was dialled: an IP address or a DNS name (also sent as SNI).
  std::error_code not_ip;
  asio::ip::make_address(host, not_ip);
  if (!not_ip) {
    X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(ssl), host.c_str());
  } else {
    SSL_set1_host(ssl, host.c_str());
    SSL_set_tlsext_host_name(ssl, host.c_str());
  }
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK);
  SSL_set_fd(ssl, fd_);
  try {
    run([ssl] { return SSL_connect(ssl); }, "TLS handshake with", tls.handshake_timeout);
  } catch (const std::runtime_error&) {
    const long verify = SSL_get_verify_result(ssl);
    if (verify != X509_V_OK) {
      const std::string reason = X509_verify_cert_error_string(verify);
      throw std::runtime_error("TLS handshake with sweepd at " + address_ +
                               ": its certificate is not accepted (" + reason +
                               (tls.ca_file.empty() ? "; --tls-ca FILE names the CA that signed it)"
                                                    : "; is it signed by " + tls.ca_file +
                                                          " and issued to " + host + "?)"));
    }
    throw;
  }
}

template <typename Call>
int TlsChannel::run(Call call, const char* what, std::chrono::milliseconds timeout) {
  for (;;) {
    int result = 0, error = SSL_ERROR_NONE;
    std::string reason;
    {
      const std::lock_guard lock(mutex_);
      const NoSigpipe no_sigpipe;
      ERR_clear_error();
      result = call();
      if (result <= 0) {
        error = SSL_get_error(ssl_.get(), result);
        reason = openssl_reason("the connection was closed");
      }
    }
    short events = 0;
    switch (error) {
      case SSL_ERROR_NONE:
        return result;
      case SSL_ERROR_WANT_READ:
        events = POLLIN;
        break;
      case SSL_ERROR_WANT_WRITE:
        events = POLLOUT;
        break;
      case SSL_ERROR_ZERO_RETURN:
        throw ConnectionLost(std::string(what) + " sweepd at " + address_ +
                             ": the server closed the connection");
      default:
        throw ConnectionLost(std::string(what) + " sweepd at " + address_ + ": TLS: " + reason);
    }
    pollfd wait{fd_, events, 0};
    if (::poll(&wait, 1, timeout.count() > 0 ? static_cast<int>(timeout.count()) : -1) == 0) {
      throw ReceiveTimeout("sweepd at " + address_ + " sent nothing for " +
                           std::to_string(timeout.count()) + " ms");
    }
  }
}

void TlsChannel::write_all(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const int size = static_cast<int>(std::min<std::size_t>(bytes.size(), kMostPerCall));
    const int n = run([&] { return SSL_write(ssl_.get(), bytes.data(), size); }, "sending to",
                      std::chrono::milliseconds(0));
    bytes = bytes.subspan(static_cast<std::size_t>(n));
  }
}

void TlsChannel::read_exactly(std::span<std::uint8_t> bytes, std::chrono::milliseconds timeout) {
  while (!bytes.empty()) {
    const int size = static_cast<int>(std::min<std::size_t>(bytes.size(), kMostPerCall));
    const int n =
        run([&] { return SSL_read(ssl_.get(), bytes.data(), size); }, "reading from", timeout);
    bytes = bytes.subspan(static_cast<std::size_t>(n));
  }
}

void TlsChannel::close() {
  const std::lock_guard lock(mutex_);
  const NoSigpipe no_sigpipe;
  SSL_shutdown(ssl_.get());  // sends close_notify; the peer's is not awaited
}

}  // namespace sweepd::client

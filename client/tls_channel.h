// TlsChannel: the client side of TLS (OpenSSL) over a connected TCP socket, for
// client::Connection. One thread may read while another writes (stream_poses reads replies
// on a thread of its own): each OpenSSL call runs under a lock on a non-blocking socket and
// waits for the socket outside it, so a blocked read never holds a write up.
//
//   TlsChannel(fd, host, address, tls)   handshake as a client: TLS 1.2 at least; the server's
//                                        certificate must chain to tls.ca_file (or the
//                                        system's store) and name `host` (DNS name or IP
//                                        address); tls.cert_file/key_file are offered when
//                                        the server asks; throws ReceiveTimeout when the
//                                        server sends nothing for tls.handshake_timeout.
//                                        Makes `fd` non-blocking.
//   write_all(bytes), read_exactly(bytes, timeout)
//                                        the whole span, or ConnectionLost (closed, a TLS
//                                        error: client/connection_lost.h); a read that
//                                        waits `timeout` (zero: for ever) for the socket
//                                        throws ReceiveTimeout
//   close()                              close_notify, best effort (the socket stays open)
// Errors are std::runtime_error naming `address` and the reason: a file that will not load
// (naming the flag), an untrusted or mismatched server certificate (with OpenSSL's verify
// reason), the server's refusal (e.g. "certificate required"), a connection closed.
// SIGPIPE from a write to a closed socket is blocked and discarded in the calling thread.
#pragma once

#include <openssl/ssl.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>

#include "client/client_tls.h"
#include "client/receive_timeout.h"

namespace sweepd::client {

class TlsChannel {
 public:
  TlsChannel(int fd, const std::string& host, const std::string& address, const ClientTls& tls);

  void write_all(std::span<const std::uint8_t> bytes);
  void read_exactly(std::span<std::uint8_t> bytes,
                    std::chrono::milliseconds timeout = std::chrono::milliseconds(0));
  void close();

 private:
  // Runs `call` (an SSL_* returning > 0 on success) until it succeeds; waits for the socket
  // (at most `timeout`, zero: for ever) when OpenSSL wants to read or write. Throws naming
  // `what` on failure or end of stream, ReceiveTimeout when the wait runs out.
  template <typename Call>
  int run(Call call, const char* what, std::chrono::milliseconds timeout);

  int fd_;
  std::string address_;
  std::unique_ptr<SSL_CTX, decltype(&SSL_CTX_free)> context_;
  std::unique_ptr<SSL, decltype(&SSL_free)> ssl_{nullptr, SSL_free};
  std::mutex mutex_;
};

}  // namespace sweepd::client

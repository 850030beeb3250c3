// ConnectionStream: the byte stream under one sweepd Connection — a plain socket (TCP or
// Unix), or TLS over a TCP socket (Asio's ssl::stream over Debian's OpenSSL). The
// Connection's framing, limits and timers are the same on both; only the bytes differ.
//
//   ConnectionStream(socket)             plain
//   ConnectionStream(socket, context)    TLS, server side; handshake() before any read/write
//   handshake(handler)                   TLS: the server handshake; plain: never called
//   async_read_some(buffer, handler)     as Asio's, on whichever stream it is
//   async_write(buffer, condition, handler)  asio::async_write on whichever stream it is
//   tls_session()                        after the handshake: protocol version, cipher and the
//                                        client certificate's subject (empty: none), for logs
//   close()                              shuts the socket down and closes it, no TLS close_notify
//                                        (a peer may read the last reply, then sees the end)
// All calls on the connection's I/O thread; one read and one write may be outstanding at once.
#pragma once

#include <asio.hpp>
#include <asio/ssl.hpp>
#include <optional>
#include <string>
#include <utility>

namespace sweepd::server {

struct TlsSession {
  std::string version;         // "TLSv1.3"
  std::string cipher;          // "TLS_AES_256_GCM_SHA384"
  std::string client_subject;  // "/CN=render-node-3"; empty without a client certificate
};

class ConnectionStream {
 public:
  using Socket = asio::generic::stream_protocol::socket;

  explicit ConnectionStream(Socket socket) : plain_(std::move(socket)) {}
  ConnectionStream(Socket socket, asio::ssl::context& context)
      : tls_(std::in_place, std::move(socket), context) {}

  bool tls() const { return tls_.has_value(); }
  Socket::executor_type get_executor() { return socket().get_executor(); }

  template <typename Handler>
  void handshake(Handler&& handler) {
    tls_->async_handshake(asio::ssl::stream_base::server, std::forward<Handler>(handler));
  }

  template <typename Buffer, typename Handler>
  void async_read_some(const Buffer& buffer, Handler&& handler) {
    if (tls_) {
      tls_->async_read_some(buffer, std::forward<Handler>(handler));
    } else {
      plain_->async_read_some(buffer, std::forward<Handler>(handler));
    }
  }

  template <typename Buffer, typename Condition, typename Handler>
  void async_write(const Buffer& buffer, Condition condition, Handler&& handler) {
    if (tls_) {
      asio::async_write(*tls_, buffer, std::move(condition), std::forward<Handler>(handler));
    } else {
      asio::async_write(*plain_, buffer, std::move(condition), std::forward<Handler>(handler));
    }
  }

  TlsSession tls_session();
  void close();

 private:
  Socket& socket() { return tls_ ? tls_->next_layer() : *plain_; }

  std::optional<Socket> plain_;
  std::optional<asio::ssl::stream<Socket>> tls_;
};

}  // namespace sweepd::server

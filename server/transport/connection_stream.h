// ConnectionStream: the byte stream under one sweepd Connection — a plain socket (TCP or
// Unix), or TLS over a TCP socket (Asio's ssl::stream over Debian's OpenSSL), either of them
// optionally carrying WebSocket (--ws-listen; WebSocketSession on websocketpp). The
// Connection's framing, limits and timers are the same on all; only the bytes differ.
//
//   ConnectionStream(socket, tls, websocket)   tls: server-side TLS context, or nullptr;
//                                       websocket: the server side of a WebSocket session,
//                                       or nullptr. Each needs its handshake first.
//   handshake(done)                     the TLS handshake, then the WebSocket one; done(failure)
//                                       with failure "" on success, else the reason (OpenSSL's,
//                                       or the HTTP refusal, which is sent first)
//   pending_handshake()                 "TLS", "WebSocket", or "" when none is due
//   async_read_some(buffer, handler)    as Asio's; on WebSocket: binary messages' payloads (the
//                                       protocol's frames), and after each read from the socket
//                                       it completes, with 0 bytes when no message was whole
//   async_write(buffer, on_progress, handler)  all of `buffer` (one frame: on WebSocket, one
//                                       binary message); on_progress() after each partial send
//   unix_socket()                       a plain Unix socket (descriptors can be passed on it)
//   async_wait_writable(handler)        plain socket: handler(error) once it takes bytes again
//   mid_message()                       WebSocket: part of a message received, the rest not yet
//   failure()                           WebSocket: why this side ended the session (a text
//                                       message, a message too big, a protocol violation); ""
//   set_max_message_bytes(n)            WebSocket: the largest message from now on; else nothing
//   tls_session()                       after the handshake: protocol version, cipher and the
//                                       client certificate's subject (empty: none), for logs
//   send_close_frame(done)              WebSocket: a close frame (1000) unless one went out
//                                       already, then done() once the queue is written; plain
//                                       or TLS: done() at once
//   close()                             ends outstanding operations and hands the socket to
//                                       close_lingering (the peer reads the last reply, then
//                                       sees the end); no TLS close_notify
// All calls on the connection's I/O thread; one read and one write may be outstanding at once.
#pragma once

#include <asio.hpp>
#include <asio/ssl.hpp>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "server/transport/websocket_session.h"

namespace sweepd::server {

struct TlsSession {
  std::string version;         // "TLSv1.3"
  std::string cipher;          // "TLS_AES_256_GCM_SHA384"
  std::string client_subject;  // "/CN=render-node-3"; empty without a client certificate
};

class ConnectionStream {
 public:
  using Socket = asio::generic::stream_protocol::socket;
  using ReadHandler = std::function<void(std::error_code, std::size_t)>;
  using HandshakeHandler = std::function<void(const std::string& failure)>;

  ConnectionStream(Socket socket, asio::ssl::context* tls,
                   std::unique_ptr<WebSocketSession> websocket);
  ConnectionStream(ConnectionStream&&) = default;  // before handshake() only
  ConnectionStream& operator=(ConnectionStream&&) = delete;
  ~ConnectionStream();

  bool tls() const { return tls_.has_value(); }
  // A plain socket's handle, for a worker's own sends (ReplySendGate); -1 on TLS or WebSocket,
  // whose bytes only the I/O thread may produce.
  int plain_socket_handle() {
    return tls_ || websocket_ ? -1 : static_cast<int>(plain_->native_handle());
  }
  bool websocket() const { return websocket_ != nullptr; }
  // A plain Unix socket: the only stream a file descriptor can cross (SharedRegion).
  bool unix_socket() {
    if (plain_socket_handle() < 0) return false;
    std::error_code error;
    const auto endpoint = plain_->local_endpoint(error);
    return !error && endpoint.protocol().family() == AF_UNIX;
  }
  // Plain socket: handler(error) once the socket takes bytes again (a send that found it full).
  template <typename Handler>
  void async_wait_writable(Handler&& handler) {
    plain_->async_wait(Socket::wait_write, std::forward<Handler>(handler));
  }
  std::string pending_handshake() const;
  Socket::executor_type get_executor() { return socket().get_executor(); }

  void handshake(HandshakeHandler done);

  template <typename Buffer, typename Handler>
  void async_read_some(const Buffer& buffer, Handler&& handler) {
    if (websocket_) {
      read_messages(asio::mutable_buffer(buffer), std::forward<Handler>(handler));
    } else {
      read_socket(buffer, std::forward<Handler>(handler));
    }
  }

  template <typename Handler>
  void async_write(asio::const_buffer buffer, std::function<void()> on_progress,
                   Handler&& handler) {
    if (websocket_ && websocket_->state() != WebSocketSession::State::kOpen) {
      // The session is closing: no message can go out.
      asio::post(get_executor(), [done = ReadHandler(std::forward<Handler>(handler))]() {
        done(asio::error::broken_pipe, 0);
      });
    } else if (websocket_) {
      websocket_->send_binary(static_cast<const std::uint8_t*>(buffer.data()), buffer.size());
      write_queue_.push_back(
          {std::move(on_progress), std::forward<Handler>(handler), buffer.size()});
      flush();
    } else {
      write_socket(buffer, std::move(on_progress), std::forward<Handler>(handler));
    }
  }

  bool mid_message() const { return websocket_ && websocket_->mid_message(); }
  std::string failure() const { return websocket_ ? websocket_->failure() : ""; }
  void set_max_message_bytes(std::size_t bytes);
  void send_close_frame(std::function<void()> done);
  TlsSession tls_session();
  void close();

 private:
  // A frame handed to the WebSocket session, answered once its bytes are on the socket.
  struct QueuedWrite {
    std::function<void()> on_progress;
    ReadHandler done;  // (error, the frame's size)
    std::size_t frame_bytes;
  };

  // What the WebSocket path's callbacks hold: this stream, or nullptr once it is gone (a
  // pong's write may complete after its Connection closed).
  struct Owner {
    ConnectionStream* stream = nullptr;
  };

  Socket& socket() { return tls_ ? tls_->next_layer() : *plain_; }

  template <typename Buffer, typename Handler>
  void read_socket(const Buffer& buffer, Handler&& handler) {
    if (tls_) {
      tls_->async_read_some(buffer, std::forward<Handler>(handler));
    } else {
      plain_->async_read_some(buffer, std::forward<Handler>(handler));
    }
  }

  // All of `buffer` in as few sends as the socket takes: asio's default completion condition
  // would cut a 0.85 MB reply into 64 KiB sends (13 system calls instead of one or two).
  template <typename Handler>
  void write_socket(asio::const_buffer buffer, std::function<void()> on_progress,
                    Handler&& handler) {
    auto all_of_it = [on_progress = std::move(on_progress)](std::error_code error,
                                                            std::size_t sent) -> std::size_t {
      if (sent > 0) on_progress();
      return error ? 0 : std::numeric_limits<std::size_t>::max();
    };
    if (tls_) {
      asio::async_write(*tls_, buffer, std::move(all_of_it), std::forward<Handler>(handler));
    } else {
      asio::async_write(*plain_, buffer, std::move(all_of_it), std::forward<Handler>(handler));
    }
  }

  void handshake_websocket(HandshakeHandler done);
  void read_messages(asio::mutable_buffer buffer, ReadHandler handler);
  // Writes what the WebSocket session has for the peer; `then` (if any) once it is written.
  void flush(std::function<void(std::error_code)> then = {});

  std::optional<Socket> plain_;
  std::optional<asio::ssl::stream<Socket>> tls_;
  bool tls_pending_ = false;
  std::unique_ptr<WebSocketSession> websocket_;
  std::shared_ptr<Owner> owner_ = std::make_shared<Owner>();  // stream set by handshake()
  std::vector<std::uint8_t> socket_input_;  // WebSocket: raw bytes read from the socket
  std::size_t payload_taken_ = 0;           // of websocket_->payload()
  bool socket_ended_ = false;
  std::error_code socket_error_;
  std::deque<QueuedWrite> write_queue_;    // frames whose bytes are in websocket_->outgoing()
  std::vector<std::uint8_t> writing_;      // bytes being written
  std::deque<QueuedWrite> being_written_;  // frames among them
  std::vector<std::function<void(std::error_code)>> after_flush_, after_writing_;
  bool flushing_ = false;
};

}  // namespace sweepd::server

// WebSocketSession: one side of a WebSocket connection (RFC 6455) — the server side of
// sweepd's --ws-listen, or a client (the tests') — on websocketpp's iostream transport
// (Debian's libwebsocketpp-dev): bytes in, bytes out, no sockets, threads or timers of its own.
// ConnectionStream does the I/O and the Connection's timers bound it.
//
// This header is plain C++17 and hides websocketpp: websocketpp 0.8.2 does not compile as
// C++20, so websocket_session.cpp is compiled as C++17 (server/CMakeLists.txt).
//
//   WebSocketSession(role, allowed_origins, max_message_bytes)
//       role kServer: waits for the HTTP upgrade request; a request from an Origin that
//       origin_refusal (server/transport/origin_policy.h) refuses is answered 403, one that is
//       not a WebSocket upgrade 426, a malformed one 400. role kClient: call
//       start_client(host, origin) to write its upgrade request. max_message_bytes bounds a
//       message (its header is checked before the payload is taken; a larger one closes with
//       1009).
//   receive(bytes, count)       bytes read from the peer, all of them, in order
//   send_binary(bytes, count)   one binary message (once open); its frame goes to outgoing()
//   outgoing()                  bytes to write to the peer, in order: the caller takes them
//                               (swap or clear); handshake replies, pongs and close frames too
//   payload()                   binary messages' payloads received and not yet taken, joined
//                               (sweepd's frames carry their own length prefix); the caller
//                               erases what it takes
//   state()                     kHandshaking, kOpen, kEnded (closed, by either side, or failed)
//   failure()                   why it ended, when this side ended it: a refused or broken
//                               handshake ("HTTP 403: ..."), a text message, a message too big
//                               or a protocol violation; empty while open or after a clean
//                               close by the peer
//   mid_message()               bytes of a message or control frame received, the rest not yet
//   set_max_message_bytes(n)    from the next message on
//   close(code, reason)         starts the closing handshake (its frame goes to outgoing())
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sweepd::server {

class WebSocketSession {
 public:
  enum class Role { kServer, kClient };
  enum class State { kHandshaking, kOpen, kEnded };

  WebSocketSession(Role role, std::vector<std::string> allowed_origins,
                   std::size_t max_message_bytes);
  ~WebSocketSession();
  WebSocketSession(const WebSocketSession&) = delete;
  WebSocketSession& operator=(const WebSocketSession&) = delete;

  void start_client(const std::string& host, const std::string& origin);
  void receive(const std::uint8_t* bytes, std::size_t count);
  void send_binary(const std::uint8_t* bytes, std::size_t count);
  // A text message (what a browser's send(string) makes): the tests' wrong kind of message.
  void send_text(const std::string& text);
  void close(std::uint16_t code, const std::string& reason);
  void set_max_message_bytes(std::size_t bytes);

  std::vector<std::uint8_t>& outgoing();
  std::vector<std::uint8_t>& payload();
  State state() const;
  const std::string& failure() const;
  bool mid_message() const;
  // The peer's close code (1000 normal, 1003 unsupported data, 1009 too big, ...); 0: none.
  std::uint16_t peer_close_code() const;
  // The HTTP status of the handshake's response (101 on success); client side: the server's.
  int http_status() const;

 private:
  struct Endpoint;
  std::unique_ptr<Endpoint> endpoint_;
};

}  // namespace sweepd::server

// Connection: a blocking client connection to sweepd over TCP (plain or TLS) or a Unix socket —
// what the C++ clients (client_examples/, `sweepctl --server`, bench/server_bench) share.
//
//   Connection connection("127.0.0.1:7878");          // or Connection(host, port)
//   Connection local("unix:/run/sweepd/sweepd.sock"); // sweepd's --unix-socket
//   Connection secure("sweepd.example:7878", tls);     // ClientTls (client/client_tls.h)
//   const Welcome& welcome = connection.hello(token, "my client");
//   const ModelInfo& info = connection.load_model("mannequin");
//   connection.send(frame);                              // any frame (protocol/messages.h)
//   const PosedVertices& reply = connection.expect<PosedVertices>();
//
// On a Unix socket, map_shared_memory(bytes) (protocol 1.10) asks for a region the server
// writes pose replies into (PoseFields::shared_offset): a same-host client's replies then
// carry no vertices, and shared_positions(reply) / shared_normals(reply) read them in place —
// valid until a later pose is written at the same offset. Two offsets let the caller read one
// reply while the next is written.
// A reply is valid until the next receive. Server errors become ServerError exceptions
// (with the code); a connection that cannot be made or breaks (closed, reset, a failed send or
// receive) ConnectionLost naming the address (client/connection_lost.h: the caller may connect
// again); frames that are not the protocol's std::runtime_error; a receive that waits longer
// than set_receive_timeout() allows ReceiveTimeout, a ConnectionLost (the connection is
// unusable then: a late reply must not be taken for the next request's).
// One thread may receive while another sends. hello() with a token over plain TCP to a peer
// that is not loopback throws (the token would cross the network in clear) unless
// tls.allow_plaintext.
#pragma once

#include <asio.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "client/client_tls.h"
#include "client/receive_timeout.h"
#include "client/tls_channel.h"
#include "protocol/messages.h"

namespace sweepd::client {

class ServerError : public std::runtime_error {
 public:
  ServerError(protocol::ErrorCode code, const std::string& message);
  protocol::ErrorCode code() const { return code_; }

 private:
  protocol::ErrorCode code_;
};

class Connection {
 public:
  // address: "HOST:PORT" ("[::1]:7878" for IPv6 literals), or "unix:PATH" (no TLS there).
  explicit Connection(const std::string& address, const ClientTls& tls = {});
  Connection(const std::string& host, const std::string& port, const ClientTls& tls = {});
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  // Hello with the token → Welcome (protocol version checked by the server).
  const protocol::Welcome& hello(std::string_view token, std::string_view client_name,
                                 protocol::PoseDelivery delivery = protocol::PoseDelivery::InOrder);
  // LoadModel: upload .glb bytes under `name`, or (empty bytes) load `name` on the server.
  const protocol::ModelInfo& load_model(const std::string& name,
                                        std::span<const std::uint8_t> glb = {});

  // MapSharedMemory (Unix socket only, once per connection): the region, mapped read-only,
  // valid while the connection lives. ServerError when the server refuses (NotAvailable on
  // TCP, InvalidArgument past its max_frame_bytes, ResourceExhausted).
  std::span<const std::uint8_t> map_shared_memory(std::uint64_t bytes);
  // A reply's float32 positions / normals in the shared region; empty when the reply is not
  // in it (in_shared_memory unset) or would reach past the region.
  std::span<const float> shared_positions(const protocol::PosedVertices& reply) const;
  std::span<const float> shared_normals(const protocol::PosedVertices& reply) const;

  // How long one receive may wait for the next bytes of a frame; zero (the default) waits
  // for ever.
  void set_receive_timeout(std::chrono::milliseconds timeout) { receive_timeout_ = timeout; }
  // Plain sockets without a receive timeout: a receive first polls the socket for up to
  // `spin` before it sleeps. A thread woken on an idle core runs again only after the
  // scheduler (and, on a virtual machine, the hypervisor) wakes that core: ~0.05 ms per
  // wake-up on the 2-core VM of docs/performance.md's figures, a third of a 72k pose. Polling spends a core
  // on the wait instead. Zero (the default) sleeps at once.
  void set_receive_spin(std::chrono::microseconds spin) { receive_spin_ = spin; }

  void send(std::span<const std::uint8_t> frame);
  // The next frame, verified. Throws std::runtime_error on a closed socket or a bad frame.
  const protocol::Message& receive() { return receive(nullptr); }
  // The next frame as a T, or ServerError when it is an Error.
  template <typename T>
  const T& expect() {
    const protocol::Message& message = receive();
    throw_if_error(message);
    if (const T* body = message.template body_as<T>()) return *body;
    throw std::runtime_error(address_ + ": unexpected reply " +
                             protocol::EnumNameBody(message.body_type()));
  }
  // Bye, then the socket is closed.
  void close(std::string_view reason = "done");
  // Shuts the socket down without a Bye, from any thread: a receive or send blocked in another
  // thread ends with ConnectionLost (a client giving up on a connection it found broken).
  void abort();

  // A builder for the caller's requests (cleared before each use by the caller).
  flatbuffers::FlatBufferBuilder& builder() { return builder_; }
  const std::string& address() const { return address_; }

 private:
  static void throw_if_error(const protocol::Message& message);
  // `descriptor` set: the frame's first bytes are read with recvmsg, and a file descriptor
  // that came with them is stored there.
  const protocol::Message& receive(int* descriptor);
  void read_exactly(std::span<std::uint8_t> bytes);
  // What a receive_spin_ of polling reads of `bytes` (all, some or none of them).
  std::size_t read_spinning(std::span<std::uint8_t> bytes);
  void connect_tcp(const std::string& host, const std::string& port, const ClientTls& tls);
  void connect_unix(const std::string& path);
  std::span<const float> shared_floats(const protocol::PosedVertices& reply,
                                       std::size_t first) const;

  std::string address_;
  bool allow_plaintext_;
  bool local_peer_ = false;  // loopback or a Unix socket: a token may go in clear
  asio::io_context io_;
  asio::generic::stream_protocol::socket socket_;
  std::chrono::milliseconds receive_timeout_{0};
  std::chrono::microseconds receive_spin_{0};
  std::unique_ptr<TlsChannel> tls_;     // null: plain TCP
  std::vector<std::uint64_t> storage_;  // 8-byte aligned for FlatBuffers
  flatbuffers::FlatBufferBuilder builder_;
  std::span<const std::uint8_t> shared_;  // the mapped region, empty until mapped
};

}  // namespace sweepd::client

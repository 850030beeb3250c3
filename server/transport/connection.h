// Connection: one client session of sweepd, on TCP, WebSocket or a Unix socket — the transport. It
// moves frames, enforces authentication, limits, backpressure and reply order, and hands each
// request to its handler (server/handlers/request_table.h: one handler per message type),
// which answers through the connection as a RequestSession; encoders (server/replies/) build the
// reply frames, and every model change goes through ModelService (server/models/). It holds no
// model state of its own. Its code, by concern: connection.cpp (the session: handshakes,
// deadlines, reading, authentication, dispatch), connection_poses.cpp (the pose queue and its
// worker jobs), connection_writing.cpp (the reply queue, writing, closing).
//
// Runs on the server's single I/O thread; only deformation and model loading go to the
// worker pool (poses whose folding runs on the GPU thread to the pool of GPU waiters, see
// CollisionService). On a plain socket the worker sends its pose reply itself when nothing is
// queued before it (ReplySendGate); the I/O thread counts the pose before it reads another
// request of that client than a pose, and writes what the socket did not take at once.
// On a TLS or WebSocket stream (ConnectionStream) the handshakes come first:
// they must be done, like Hello, within config.hello_timeout_ms, or the connection is cut
// (`connection_cut`, no reply: there is no channel to send it on); a failed handshake (a
// plaintext client on the TLS port, a missing or untrusted client certificate, an HTTP request
// that is no WebSocket upgrade, a refused Origin) is cut with its reason (OpenSSL's, or the HTTP
// status sent back). On WebSocket each frame travels as one binary message; a text message, a
// message past the frame limit (before Hello: max_hello_frame_bytes) or a broken WebSocket
// frame ends the session with a WebSocket close code and a `connection_cut`. Frames are read
// with protocol::FrameReader; the first must be Hello (token compared in constant time), anything
// else before it — or no Hello within config.hello_timeout_ms — is a fatal NotAuthenticated, and
// before it a frame may have at most config.max_hello_frame_bytes (a fatal FrameTooLarge). Until
// Hello a connection is a stranger (Server sheds the oldest past config.max_strangers); a wrong
// token is counted per peer address (AuthBackoff: past config.auth_free_failures the address's
// next token waits), and a right one is admitted while fewer than config.max_connections are
// authenticated (else a fatal ConnectionLimit). Frame
// errors (BadFrame, WrongIdentifier, FrameTooLarge, ResourceExhausted) and request errors
// (UnknownModel, WrongJointCount, InvalidPose, ...) are answered with an Error and the session goes
// on, until config.max_frame_errors bad frames close it.
//
// Hostile peers are cut off, each with a `connection_cut` log line naming the reason: a frame
// not whole within frame_timeout_ms (trickled bytes), no request and no work for
// idle_timeout_ms, a client that takes no reply bytes for send_timeout_ms or lets its unread
// replies pass max_send_queue_bytes. Frames being read and replies waiting to be written take
// their bytes from the server's protocol::BufferBudget (max_buffered_bytes, shared by all
// connections).
//
// Poses run one at a time per connection, in order. InOrder delivery: at most
// max_poses_in_flight poses are queued (or replies waiting to be written); beyond that the
// connection stops reading the socket (TCP backpressure). LatestWins: a queued pose is
// replaced by a newer one, and the next reply's dropped_before counts the drops.
// Bye (from the client) or shut_down() (SIGTERM): work already received is finished and
// answered, then the server sends Bye (on shutdown) and closes.
#pragma once

#include <asio.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "protocol/framing.h"
#include "server/handlers/pose_request.h"
#include "server/handlers/request_error.h"
#include "server/handlers/request_session.h"
#include "server/transport/connection_counters.h"
#include "server/transport/connection_environment.h"
#include "server/transport/connection_stream.h"
#include "server/transport/fair_work_queue.h"
#include "server/transport/reply_send_gate.h"
#include "server/transport/shared_region.h"

namespace sweepd::server {

class Connection final : public std::enable_shared_from_this<Connection>, public RequestSession {
 public:
  // `peer`: the address and port, as logged; `address`: the peer's address alone (unix: all
  // Unix-socket peers), whose strangers and failed authentications are counted together.
  Connection(ConnectionStream stream, std::uint64_t id, std::string peer, std::string address,
             ConnectionEnvironment& environment);

  void start();
  // Not authenticated yet, and not cut or closed: it holds one of the strangers' slots.
  bool stranger() const { return !authenticated_ && !draining_ && !closed_; }
  // A stranger whose slot a newer one takes: a fatal ConnectionLimit naming `reason`, closed.
  void shed(const std::string& reason);
  // SIGTERM: new work is answered with ShuttingDown; in-flight work finishes; then Bye.
  void shut_down();

  std::uint64_t id() const { return counters_.connection_id; }
  bool websocket() const { return stream_.websocket(); }
  const ConnectionCounters& counters() const { return counters_; }
  std::size_t poses_waiting() const { return waiting_poses_.size(); }
  bool pose_running() const { return pose_running_; }

  // RequestSession, for the request handlers.
  std::uint64_t connection_id() const override { return id(); }
  ConnectionEnvironment& environment() override { return environment_; }
  flatbuffers::FlatBufferBuilder take_builder() override;
  void send(flatbuffers::FlatBufferBuilder builder) override { queue_reply(std::move(builder)); }
  void send_error(const RequestError& error, std::uint64_t request_id) override;
  void queue_pose(std::variant<PoseRequest, RequestError> intake,
                  std::uint64_t request_id) override;
  void run_in_order(Pool pool, std::function<Reply()> work) override;
  void drain() override;  // stop taking work; close once in-flight work is answered
  protocol::PoseDelivery delivery() const override { return delivery_; }
  std::weak_ptr<RequestSession> weak_session() override { return shared_from_this(); }
  bool draining() const override { return draining_; }
  bool unix_socket() override { return stream_.unix_socket(); }
  const SharedRegion* shared_region() const override { return shared_region_.get(); }
  void send_region(std::shared_ptr<const SharedRegion> region,
                   flatbuffers::FlatBufferBuilder reply) override;

 private:
  using Clock = std::chrono::steady_clock;

  // TLS: the handshake, then `next`; a failure cuts the connection. Plain: `next` at once.
  void secure_then(std::function<void()> next);
  void read_more();
  void process_input();
  bool reading_paused() const;
  void dispatch(const protocol::Message& message);
  void authenticate(const protocol::Hello& hello, std::uint64_t request_id);
  // Compares the token unless the peer's address must wait (AuthBackoff); false: refused.
  bool token_accepted(const protocol::Hello& hello, std::uint64_t request_id);

  void start_next_pose();
  // A pose answered: the connection's, the traffic's and the model's counters.
  void count_pose(const PoseRequest& request, std::uint64_t deform_ns);
  // Its reply: `sent` is what its worker sent itself (ReplySendGate), nullopt if nothing.
  void deliver_pose(flatbuffers::FlatBufferBuilder builder, std::optional<std::size_t> sent);
  // Queues a reply to be written, or (`already_sent` > 0: a worker's short send) the rest of
  // one, ahead of the queue.
  void queue_reply(flatbuffers::FlatBufferBuilder builder, std::size_t already_sent = 0);
  void send_error(protocol::ErrorCode code, const std::string& message, std::uint64_t sequence,
                  std::uint64_t request_id, bool fatal = false);
  void write_next();
  // The SharedMemory reply's first bytes with the region's descriptor; false while the socket
  // takes nothing (write_next runs again once it does).
  bool write_descriptor();
  void close_if_done();
  void close_now();
  // Logs `connection_cut` with the reason and answers a fatal error (closed once it is sent;
  // before a TLS handshake is done, closed at once).
  void cut(protocol::ErrorCode code, const std::string& reason);
  // The Hello (and TLS handshake) deadline; the frame, idle and send deadlines, re-armed as
  // bytes move.
  void arm_hello_deadline();
  void watch_frame();
  // Part of a frame read, or (WebSocket) part of the message that carries it.
  bool mid_frame() const;
  void arm_idle_deadline();
  void arm_send_deadline();
  bool has_work() const;

  ConnectionStream stream_;
  std::string address_;
  ConnectionEnvironment& environment_;
  asio::steady_timer hello_deadline_;
  asio::steady_timer frame_deadline_;  // armed while a frame is part-read
  asio::steady_timer idle_deadline_;
  asio::steady_timer send_deadline_;  // armed while a reply is being written
  bool frame_deadline_armed_ = false;
  Clock::time_point last_send_progress_{};
  std::uint32_t frame_errors_ = 0;
  std::size_t queued_reply_bytes_ = 0;  // outgoing_, taken from the buffer budget
  protocol::FrameReader reader_;
  std::vector<std::uint8_t> read_buffer_;
  std::span<const std::uint8_t> input_;
  bool reading_ = false;
  bool secured_ = false;  // TLS handshake done, or a plain stream
  bool authenticated_ = false;
  bool draining_ = false;       // Bye, end of stream, a fatal error or shutdown
  bool shutting_down_ = false;  // shutdown: send Bye when drained
  bool bye_sent_ = false;
  bool close_frame_sent_ = false;  // WebSocket: the close frame before the socket closes
  bool closed_ = false;
  int loads_running_ = 0;
  protocol::PoseDelivery delivery_ = protocol::PoseDelivery::InOrder;
  std::deque<PoseRequest> waiting_poses_;
  bool pose_running_ = false;
  FairShare fair_share_;  // this connection's turn on environment_.workers
  std::uint32_t dropped_since_reply_ = 0;
  std::deque<flatbuffers::FlatBufferBuilder> outgoing_;
  std::size_t front_sent_ = 0;  // bytes of outgoing_.front() a worker sent
  bool writing_ = false;
  // A worker sent a pose reply the I/O thread has not counted yet; a request other than a pose
  // read meanwhile waits in `deferred_` until it has (process_input).
  std::atomic<bool> reply_uncounted_{false};
  const protocol::Message* deferred_ = nullptr;
  // MapSharedMemory's region (its bytes taken from the buffer budget until close), and the
  // SharedMemory reply, queued in outgoing_, that carries its descriptor until it is sent.
  std::shared_ptr<const SharedRegion> shared_region_;
  const std::uint8_t* descriptor_frame_ = nullptr;
  ReplySendGate gate_;          // the socket: the I/O thread's writes or a worker's own send
  PosedVerticesWriter writer_;  // used by one worker job at a time
  ConnectionCounters counters_;
};

}  // namespace sweepd::server

#include "server/transport/connection.h"

#include <algorithm>
#include <utility>

#include "protocol/messages.h"
#include "server/handlers/client_string_limits.h"
#include "server/handlers/request_table.h"
#include "server/log_event.h"
#include "server/replies/welcome_reply.h"
#include "server/transport/constant_time_equal.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;
constexpr std::size_t kReadChunkBytes = 64 * 1024;

// A TLS client's first bytes read as a length prefix: a handshake record's type 0x16 and
// version 0x03 0x0N (N = 1 to 4) make the prefix's low bytes 0x0316 and its value > 64 KiB.
bool starts_like_tls_handshake(std::uint64_t declared_bytes) {
  const std::uint64_t minor = (declared_bytes >> 16) & 0xff;
  return (declared_bytes & 0xffff) == 0x0316 && minor >= 1 && minor <= 4;
}

}  // namespace

Connection::Connection(ConnectionStream stream, std::uint64_t id, std::string peer,
                       std::string address, ConnectionEnvironment& environment)
    : stream_(std::move(stream)),
      address_(std::move(address)),
      environment_(environment),
      hello_deadline_(stream_.get_executor()),
      frame_deadline_(stream_.get_executor()),
      idle_deadline_(stream_.get_executor()),
      send_deadline_(stream_.get_executor()),
      // Before Hello only a small frame: an unauthenticated peer cannot make the server buffer.
      reader_(
          std::min(environment.config.max_hello_frame_bytes, environment.config.max_frame_bytes),
          &environment.buffer_budget),
      read_buffer_(kReadChunkBytes),
      gate_(stream_.plain_socket_handle()),
      writer_(environment.config.deform_threads, environment.spare_cores, environment.collision) {
  counters_.connection_id = id;
  counters_.peer = std::move(peer);
  secured_ = stream_.pending_handshake().empty();
  // Before Hello only a small message too: websocketpp takes a message whole before the frame
  // reader sees it.
  stream_.set_max_message_bytes(reader_.max_frame_bytes() + protocol::kLengthPrefixBytes);
}

void Connection::start() {
  log_event("connection_open", {{"connection", id()},
                                {"peer", counters_.peer},
                                {"tls", stream_.tls()},
                                {"websocket", stream_.websocket()}});
  arm_hello_deadline();
  arm_idle_deadline();
  secure_then([self = shared_from_this()]() { self->read_more(); });
}

void Connection::shed(const std::string& reason) {
  ++environment_.traffic.strangers_shed;
  cut(pb::ErrorCode::ConnectionLimit, reason);
}

void Connection::secure_then(std::function<void()> next) {
  if (secured_) {
    next();
    return;
  }
  stream_.handshake(
      [self = shared_from_this(), next = std::move(next)](const std::string& failure) {
        if (self->closed_) return;
        if (!failure.empty()) {
          self->cut(pb::ErrorCode::NotAuthenticated, failure);
          return;
        }
        self->secured_ = true;
        if (self->stream_.tls()) {
          const TlsSession session = self->stream_.tls_session();
          log_event("tls_established", {{"connection", self->id()},
                                        {"version", session.version},
                                        {"cipher", session.cipher},
                                        {"client_certificate", session.client_subject}});
        }
        if (self->stream_.websocket()) log_event("websocket_open", {{"connection", self->id()}});
        next();
      });
}

void Connection::shut_down() {
  shutting_down_ = true;
  drain();
}

void Connection::cut(pb::ErrorCode code, const std::string& reason) {
  log_event("connection_cut", {{"connection", id()}, {"peer", counters_.peer}, {"reason", reason}});
  if (!secured_) {  // before the TLS handshake there is no channel to send an Error on
    close_now();
    return;
  }
  send_error(code, reason, 0, 0, true);
}

// ---------------------------------------------------------------------------------------
// Deadlines: a timer that fires after its connection closed, or was re-armed, does nothing.

void Connection::arm_hello_deadline() {
  hello_deadline_.expires_after(std::chrono::milliseconds(environment_.config.hello_timeout_ms));
  hello_deadline_.async_wait([self = shared_from_this()](std::error_code error) {
    if (error || self->authenticated_ || self->draining_ || self->closed_) return;
    const std::string timeout = std::to_string(self->environment_.config.hello_timeout_ms);
    if (!self->secured_) {
      self->cut(pb::ErrorCode::NotAuthenticated,
                "no " + self->stream_.pending_handshake() + " handshake within " + timeout + " ms");
      return;
    }
    self->send_error(pb::ErrorCode::NotAuthenticated, "no Hello within " + timeout + " ms", 0, 0,
                     true);
  });
}

bool Connection::mid_frame() const { return reader_.mid_frame() || stream_.mid_message(); }

void Connection::watch_frame() {
  if (!mid_frame()) {
    if (frame_deadline_armed_) frame_deadline_.cancel();
    frame_deadline_armed_ = false;
    return;
  }
  if (frame_deadline_armed_) return;
  frame_deadline_armed_ = true;
  const std::uint32_t timeout_ms = environment_.config.frame_timeout_ms;
  frame_deadline_.expires_after(std::chrono::milliseconds(timeout_ms));
  frame_deadline_.async_wait([self = shared_from_this(), timeout_ms](std::error_code error) {
    if (error || self->closed_ || self->draining_ || !self->mid_frame()) return;
    self->cut(pb::ErrorCode::BadFrame,
              "a frame was not whole within " + std::to_string(timeout_ms) + " ms");
  });
}

bool Connection::has_work() const {
  return pose_running_ || !waiting_poses_.empty() || loads_running_ > 0 || !outgoing_.empty() ||
         mid_frame();
}

void Connection::arm_idle_deadline() {
  const std::uint32_t timeout_ms = environment_.config.idle_timeout_ms;
  if (timeout_ms == 0) return;
  idle_deadline_.expires_after(std::chrono::milliseconds(timeout_ms));
  idle_deadline_.async_wait([self = shared_from_this(), timeout_ms](std::error_code error) {
    if (error || self->closed_ || self->draining_) return;
    if (self->has_work()) {
      self->arm_idle_deadline();  // busy, not idle: look again later
      return;
    }
    self->cut(pb::ErrorCode::Internal,
              "idle: no request for " + std::to_string(timeout_ms) + " ms; closing");
  });
}

void Connection::arm_send_deadline() {
  const auto timeout = std::chrono::milliseconds(environment_.config.send_timeout_ms);
  send_deadline_.expires_at(last_send_progress_ + timeout);
  send_deadline_.async_wait([self = shared_from_this(), timeout](std::error_code error) {
    if (error || self->closed_ || !self->writing_) return;
    if (Clock::now() - self->last_send_progress_ < timeout) {
      self->arm_send_deadline();  // the client took bytes meanwhile
      return;
    }
    // It reads nothing, so no Error would reach it: closed at once.
    log_event("connection_cut", {{"connection", self->id()},
                                 {"peer", self->counters_.peer},
                                 {"reason", "the client took no reply bytes for " +
                                                std::to_string(timeout.count()) + " ms"}});
    self->close_now();
  });
}

// ---------------------------------------------------------------------------------------
// Reading.

void Connection::read_more() {
  if (reading_ || closed_ || (draining_ && !shutting_down_)) return;
  reading_ = true;
  stream_.async_read_some(asio::buffer(read_buffer_), [self = shared_from_this()](
                                                          std::error_code error, std::size_t n) {
    self->reading_ = false;
    if (self->closed_) return;
    if (error) {
      if (const std::string failure = self->stream_.failure(); !failure.empty()) {
        log_event(
            "connection_cut",
            {{"connection", self->id()}, {"peer", self->counters_.peer}, {"reason", failure}});
      } else if (self->mid_frame()) {
        log_event("truncated_frame", {{"connection", self->id()}});
      }
      self->draining_ = true;
      self->close_if_done();
      return;
    }
    self->counters_.bytes_in += n;
    self->input_ = std::span<const std::uint8_t>(self->read_buffer_.data(), n);
    self->arm_idle_deadline();
    self->process_input();
    self->watch_frame();
  });
}

bool Connection::reading_paused() const {
  if (loads_running_ > 0) return true;  // keep replies in request order around a long load
  if (delivery_ == pb::PoseDelivery::LatestWins) {
    return outgoing_.size() >= environment_.config.max_poses_in_flight;
  }
  const std::size_t in_flight = waiting_poses_.size() + (pose_running_ ? 1 : 0);
  return std::max(in_flight, outgoing_.size()) >= environment_.config.max_poses_in_flight;
}

void Connection::process_input() {
  if (deferred_ != nullptr) {
    if (reply_uncounted_.load(std::memory_order_acquire) || closed_) return;
    dispatch(*std::exchange(deferred_, nullptr));
  }
  while (!input_.empty() && !closed_ && !reading_paused()) {
    if (draining_ && !shutting_down_) {
      input_ = {};  // after Bye or a fatal error nothing more is read
      break;
    }
    pb::FrameEvent event = reader_.read(input_);
    if (event.status == pb::FrameStatus::kPending) break;
    if (event.status == pb::FrameStatus::kError) {
      log_event("frame_error", {{"connection", id()},
                                {"error", pb::frame_error_name(event.error)},
                                {"reason", event.reason}});
      if (!authenticated_ && event.error == pb::FrameError::kOversized) {
        cut(pb::ErrorCode::FrameTooLarge,
            starts_like_tls_handshake(event.declared_bytes)
                ? "a TLS handshake on a plain port (this listener has no --tls-cert)"
                : "before Hello a frame may have at most " +
                      std::to_string(reader_.max_frame_bytes()) + " bytes; this one declares " +
                      std::to_string(event.declared_bytes));
        continue;
      }
      send_error(pb::error_code_for(event.error), event.reason, 0, 0);
      // Running out of the shared budget is not this client's fault; garbage is.
      if (event.error != pb::FrameError::kOverBudget &&
          ++frame_errors_ >= environment_.config.max_frame_errors) {
        cut(pb::ErrorCode::BadFrame,
            std::to_string(frame_errors_) + " bad frames on this connection; closing");
      }
      continue;
    }
    if (event.message->body_type() != pb::Body::Pose &&
        reply_uncounted_.load(std::memory_order_acquire)) {
      deferred_ = event.message;  // valid until the reader's next read: none until dispatched
      return;
    }
    dispatch(*event.message);
  }
  if (input_.empty()) read_more();
}

// ---------------------------------------------------------------------------------------
// Requests: authentication here, the rest to their handlers (server/handlers/request_table.h).

void Connection::dispatch(const pb::Message& message) {
  const std::uint64_t request_id = message.request_id();
  environment_.traffic.count_request(message.body_type());
  if (!authenticated_ && message.body_type() != pb::Body::Hello) {
    send_error(pb::ErrorCode::NotAuthenticated, "the first message must be Hello", 0, request_id,
               true);
    return;
  }
  if (const std::optional<RequestError> refusal = find_overlong_string(message)) {
    send_error(*refusal, request_id);
    return;
  }
  if (!authenticated_) {
    authenticate(*message.body_as_Hello(), request_id);
    return;
  }
  if (shutting_down_) {
    send_error(pb::ErrorCode::ShuttingDown, "the server is shutting down and takes no new work", 0,
               request_id);
    return;
  }
  if (const RequestHandler handler = handler_for(message.body_type())) {
    handler(message, *this);
    return;
  }
  send_error(pb::ErrorCode::UnknownMessage,
             "message type " + std::to_string(static_cast<int>(message.body_type())) +
                 " is not a request this server answers",
             0, request_id);
}

void Connection::authenticate(const pb::Hello& hello, std::uint64_t request_id) {
  counters_.client_name = hello.client_name() ? hello.client_name()->str() : "";
  if (hello.version_major() != pb::kProtocolVersionMajor) {
    send_error(pb::ErrorCode::VersionMismatch,
               "client protocol " + std::to_string(hello.version_major()) + "." +
                   std::to_string(hello.version_minor()) + " is not compatible with server " +
                   std::to_string(pb::kProtocolVersionMajor) + "." +
                   std::to_string(pb::kProtocolVersionMinor),
               0, request_id, true);
    return;
  }
  if (!environment_.config.token.empty() && !token_accepted(hello, request_id)) return;
  if (environment_.members_open >= environment_.config.max_connections) {
    send_error(pb::ErrorCode::ConnectionLimit,
               "the server already holds its limit of " +
                   std::to_string(environment_.config.max_connections) +
                   " authenticated connections",
               0, request_id, true);
    return;
  }
  authenticated_ = true;
  ++environment_.members_open;
  hello_deadline_.cancel();
  reader_.set_max_frame_bytes(environment_.config.max_frame_bytes);
  stream_.set_max_message_bytes(environment_.config.max_frame_bytes + protocol::kLengthPrefixBytes);
  delivery_ = hello.delivery() == pb::PoseDelivery::LatestWins ? pb::PoseDelivery::LatestWins
                                                               : pb::PoseDelivery::InOrder;
  log_event("hello", {{"connection", id()},
                      {"client", counters_.client_name},
                      {"delivery", pb::EnumNamePoseDelivery(delivery_)}});
  flatbuffers::FlatBufferBuilder builder = take_builder();
  build_welcome(builder, environment_.config, environment_.position_maps.enabled(),
                stream_.unix_socket(), id(), request_id);
  send(std::move(builder));
}

bool Connection::token_accepted(const pb::Hello& hello, std::uint64_t request_id) {
  const auto now = Clock::now();
  AuthBackoff& backoff = environment_.auth_backoff;
  if (const std::chrono::milliseconds wait = backoff.wait(address_, now); wait.count() > 0) {
    ++environment_.traffic.auth_backoff_refusals;
    send_error(pb::ErrorCode::AuthFailed,
               "too many wrong tokens from " + address_ + ": no token from it is checked for " +
                   std::to_string(wait.count()) + " ms",
               0, request_id, true);
    return false;
  }
  const std::string_view token =
      hello.auth_token() ? hello.auth_token()->string_view() : std::string_view();
  if (constant_time_equal(environment_.config.token, token)) return true;
  ++environment_.traffic.auth_failures;
  // Once per burst; the burst's counts are logged when it ends (auth_failure_burst).
  if (backoff.failed(address_, now)) {
    log_event("auth_failed", {{"connection", id()},
                              {"peer", counters_.peer},
                              {"burst", "first wrong token from this address; the rest are "
                                        "counted in its auth_failure_burst line"}});
  }
  send_error(pb::ErrorCode::AuthFailed, "the auth token is wrong", 0, request_id, true);
  return false;
}

void Connection::run_in_order(Pool pool, std::function<Reply()> work) {
  ++loads_running_;  // reading pauses until the reply is queued (reading_paused)
  auto job = [self = shared_from_this(), work = std::move(work)]() {
    Reply reply = work();
    asio::post(self->stream_.get_executor(), [self, reply = std::move(reply)]() {
      --self->loads_running_;
      reply(*self);
      self->process_input();
    });
  };
  if (pool == Pool::kGpuWaiters) {
    asio::post(environment_.gpu_waiters, std::move(job));
  } else {
    environment_.workers.post(fair_share_, std::move(job));
  }
}

}  // namespace sweepd::server

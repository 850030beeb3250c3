#include "server/transport/connection_stream.h"

#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "server/transport/lingering_close.h"

namespace sweepd::server {
namespace {

constexpr std::size_t kSocketReadBytes = 64 * 1024;

}  // namespace

ConnectionStream::ConnectionStream(Socket socket, asio::ssl::context* tls,
                                   std::unique_ptr<WebSocketSession> websocket)
    : tls_pending_(tls != nullptr), websocket_(std::move(websocket)) {
  if (tls != nullptr) {
    tls_.emplace(std::move(socket), *tls);
  } else {
    plain_.emplace(std::move(socket));
  }
  if (websocket_) socket_input_.resize(kSocketReadBytes);
}

ConnectionStream::~ConnectionStream() {
  if (owner_) owner_->stream = nullptr;
}

std::string ConnectionStream::pending_handshake() const {
  if (tls_pending_) return "TLS";
  if (websocket_ && websocket_->state() == WebSocketSession::State::kHandshaking)
    return "WebSocket";
  return "";
}

void ConnectionStream::handshake(HandshakeHandler done) {
  owner_->stream = this;  // where it stays: the callbacks below may outlive a moved-from one
  if (!tls_pending_) {
    handshake_websocket(std::move(done));
    return;
  }
  tls_->async_handshake(asio::ssl::stream_base::server,
                        [this, done = std::move(done)](std::error_code error) {
                          if (error) {
                            done("TLS handshake failed: " + error.message());
                            return;
                          }
                          tls_pending_ = false;
                          handshake_websocket(done);
                        });
}

void ConnectionStream::handshake_websocket(HandshakeHandler done) {
  if (!websocket_ || websocket_->state() == WebSocketSession::State::kOpen) {
    done("");
    return;
  }
  if (websocket_->state() == WebSocketSession::State::kEnded) {
    // The HTTP refusal (403, 426, 400) reaches the client before the close.
    const std::string failure = websocket_->failure();
    flush([done, failure](std::error_code) { done(failure); });
    return;
  }
  read_socket(asio::buffer(socket_input_),
              [owner = owner_, done = std::move(done)](std::error_code error, std::size_t n) {
                ConnectionStream* self = owner->stream;
                if (self == nullptr) return;
                if (error) {
                  done("WebSocket handshake failed: " + error.message());
                  return;
                }
                self->websocket_->receive(self->socket_input_.data(), n);
                self->flush();
                self->handshake_websocket(done);
              });
}

void ConnectionStream::read_messages(asio::mutable_buffer buffer, ReadHandler handler) {
  std::vector<std::uint8_t>& payload = websocket_->payload();
  const std::size_t available = payload.size() - payload_taken_;
  if (available > 0 || socket_ended_ || websocket_->state() != WebSocketSession::State::kOpen) {
    const std::size_t n = std::min(available, buffer.size());
    // n == 0 where nothing was ever received: payload.data() is null, which memcpy may not take.
    if (n > 0) std::memcpy(buffer.data(), payload.data() + payload_taken_, n);
    payload_taken_ += n;
    if (payload_taken_ == payload.size()) {
      payload.clear();  // keeps its capacity for the next messages
      payload_taken_ = 0;
    }
    std::error_code error;
    if (n == 0) {
      error = !websocket_->failure().empty() ? std::make_error_code(std::errc::protocol_error)
              : socket_error_                ? socket_error_
                                             : asio::error::eof;
    }
    asio::post(get_executor(), [handler = std::move(handler), error, n]() { handler(error, n); });
    return;
  }
  read_socket(asio::buffer(socket_input_), [owner = owner_, buffer, handler = std::move(handler)](
                                               std::error_code error, std::size_t n) {
    ConnectionStream* self = owner->stream;
    if (self == nullptr) return;
    if (error) {
      self->socket_ended_ = true;
      self->socket_error_ = error;
    } else {
      self->websocket_->receive(self->socket_input_.data(), n);
      self->flush();  // pongs, and the close frame that answers the peer's
    }
    const std::vector<std::uint8_t>& payload = self->websocket_->payload();
    if (payload.size() == self->payload_taken_ && !self->socket_ended_ &&
        self->websocket_->state() == WebSocketSession::State::kOpen) {
      handler({}, 0);  // no message whole yet: the caller looks at its deadlines
      return;
    }
    self->read_messages(buffer, handler);
  });
}

void ConnectionStream::flush(std::function<void(std::error_code)> then) {
  if (then) after_flush_.push_back(std::move(then));
  if (flushing_) return;
  std::vector<std::uint8_t>& outgoing = websocket_->outgoing();
  if (outgoing.empty()) {
    // Nothing left to write: whoever waited for the flush is done.
    for (auto& waiting : std::exchange(after_flush_, {})) waiting({});
    return;
  }
  flushing_ = true;
  writing_.swap(outgoing);
  outgoing.clear();
  being_written_.swap(write_queue_);
  after_writing_.swap(after_flush_);
  write_socket(
      asio::buffer(writing_),
      [owner = owner_]() {
        if (owner->stream == nullptr) return;
        for (const QueuedWrite& frame : owner->stream->being_written_) frame.on_progress();
      },
      [owner = owner_](std::error_code error, std::size_t) {
        ConnectionStream* self = owner->stream;
        if (self == nullptr) return;
        self->flushing_ = false;
        self->writing_.clear();
        std::deque<QueuedWrite> written = std::exchange(self->being_written_, {});
        std::vector<std::function<void(std::error_code)>> waiting =
            std::exchange(self->after_writing_, {});
        for (QueuedWrite& frame : written) frame.done(error, error ? 0 : frame.frame_bytes);
        for (auto& then : waiting) then(error);
        // A callback may have closed the stream; a later write fails at once, harmlessly.
        if (!error && owner->stream != nullptr) self->flush();
      });
}

void ConnectionStream::set_max_message_bytes(std::size_t bytes) {
  if (websocket_) websocket_->set_max_message_bytes(bytes);
}

void ConnectionStream::send_close_frame(std::function<void()> done) {
  if (!websocket_) {
    done();
    return;
  }
  // Normal closure: a fatal Error frame, if any, said why. A session already closing has its
  // close frame (or the answer to the peer's) in the queue: that goes out first all the same.
  if (websocket_->state() == WebSocketSession::State::kOpen) websocket_->close(1000, "");
  flush([done = std::move(done)](std::error_code) { done(); });
}

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
  // Outstanding reads and writes end now (their handlers see operation_aborted); the socket
  // lingers on its own until the peer has read what was sent.
  std::error_code ignored;
  socket().cancel(ignored);
  close_lingering(std::move(socket()));
}

}  // namespace sweepd::server

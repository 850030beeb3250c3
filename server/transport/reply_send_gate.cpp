#include "server/transport/reply_send_gate.h"

#include <sys/socket.h>

#include <cerrno>

namespace sweepd::server {

std::optional<std::size_t> ReplySendGate::try_send(std::span<const std::uint8_t> bytes) {
  if (handle_ < 0) return std::nullopt;
  const std::lock_guard lock(mutex_);
  if (closed_ || owner_ != Owner::kNone) return std::nullopt;
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n =
        ::send(handle_, bytes.data() + sent, bytes.size() - sent, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;  // no room (the I/O thread waits for it) or an error (its write reports it)
    }
  }
  if (sent < bytes.size()) owner_ = Owner::kRemainder;
  return sent;
}

void ReplySendGate::take_remainder() {
  const std::lock_guard lock(mutex_);
  owner_ = Owner::kIoThread;
}

bool ReplySendGate::acquire() {
  const std::lock_guard lock(mutex_);
  if (owner_ == Owner::kRemainder) return false;
  owner_ = Owner::kIoThread;
  return true;
}

void ReplySendGate::release() {
  const std::lock_guard lock(mutex_);
  if (owner_ == Owner::kIoThread) owner_ = Owner::kNone;
}

void ReplySendGate::close() {
  const std::lock_guard lock(mutex_);
  closed_ = true;
}

}  // namespace sweepd::server

// ReplySendGate: who may write a connection's plain socket now — the I/O thread, working
// through its queue of replies, or the worker that just built a pose reply and sends it
// itself. A worker's own send spares the reply a trip through the I/O thread's queue: under
// 32 streaming clients that queue held a new connection's first reply for ~10 ms, the I/O
// thread being one thread among the clients' on two cores.
//
//   ReplySendGate gate(socket_handle);       // -1: never sent by a worker (TLS, WebSocket)
//   gate.try_send(bytes)                     // worker: nullopt when the I/O thread has the
//                                            // socket or replies queued (nothing sent); else
//                                            // the bytes the socket took without waiting. When
//                                            // short, the gate stays held for the remainder.
//   gate.take_remainder()                    // I/O thread: the worker's remainder is its own now
//   gate.acquire()                           // I/O thread, before a write: false while a
//                                            // worker's remainder waits for take_remainder()
//   gate.release()                           // I/O thread: its queue is empty
//   gate.close()                             // I/O thread, before the socket closes: no send
//                                            // starts after it, none is under way when it returns
// A worker sends only when the I/O thread has nothing queued, so replies keep the order they
// would have had in the queue; the lock is held through the (non-blocking) send so that the
// socket cannot be closed under it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>

namespace sweepd::server {

class ReplySendGate {
 public:
  explicit ReplySendGate(int socket_handle) : handle_(socket_handle) {}

  std::optional<std::size_t> try_send(std::span<const std::uint8_t> bytes);
  void take_remainder();
  bool acquire();
  void release();
  void close();

 private:
  enum class Owner { kNone, kIoThread, kRemainder };

  const int handle_;
  std::mutex mutex_;
  Owner owner_ = Owner::kNone;
  bool closed_ = false;
};

}  // namespace sweepd::server

// HostilePeers: server_bench's attackers — raw loopback connections that misbehave the ways
// protocol/README.md's session rule 4 guards against, `per_kind` of each:
//   oversized   a 1 MiB length prefix before Hello;
//   tricklers   Hello, then a 16 MiB frame sent one byte per connection every 100 ms;
//   non-readers Hello, then 40 copies of `pose_frame` with a 4 KiB receive buffer, never read;
//   garbage     Hello, then 20 frames of junk.
// start() opens them all (and the trickling thread); the destructor closes every socket.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <thread>
#include <vector>

namespace sweepd::bench {

class HostilePeers {
 public:
  HostilePeers(int port, std::span<const std::uint8_t> pose_frame, int per_kind);
  ~HostilePeers();
  HostilePeers(const HostilePeers&) = delete;
  HostilePeers& operator=(const HostilePeers&) = delete;

  int count() const { return static_cast<int>(sockets_.size()); }

 private:
  int open(int receive_buffer_bytes = 0);

  int port_;
  std::vector<int> sockets_, tricklers_;
  std::atomic<bool> trickling_{true};
  std::thread trickle_;
};

}  // namespace sweepd::bench

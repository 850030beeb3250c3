// HostileDoors: every attack of issue 49 at once on every door of one daemon, for the hostile
// load test (tests/server/daemon_hostile_load_test.cpp) and its benchmark
// (bench/hostile_load_bench.cpp). On each stream door given — TCP, the Unix socket, WebSocket
// (its upgrade sent, every frame one masked binary message, the replies never read) — `per_kind`
// peers of each kind:
//   silent      connects and never sends a byte (holds a stranger's slot)
//   oversized   a 1 MiB length prefix before Hello
//   trickler    Hello, then a 16 MiB frame, one byte every 100 ms
//   non-reader  Hello, 40 copies of `pose_frame`, a 4 KiB receive buffer never read
//   garbage     Hello, 20 frames of junk
//   fuzzed      Hello, 20 copies of `pose_frame` with 1 to 8 bytes of each changed (a fixed
//               seed: the same bytes every run)
//   bad token   every 100 ms a new connection whose Hello has a wrong token (not on the Unix
//               socket: its peers share one address, so a same-host guesser there makes every
//               Unix client wait out its back-off — auth_backoff.h; said in the report)
// and on the HTTP side port, 4 × per_kind slowloris peers (a request head one byte every
// 100 ms, a new one when the side port cuts it). The authenticated kinds send `token` (a client
// holding a valid token and misbehaving); the bad tokens are `token` + "x". TCP and WebSocket
// peers connect from 127.0.0.2, so that their per-address quotas are not the honest clients'
// (127.0.0.1): an attacker on another host. `kinds` picks the kinds (all by default; server_bench
// sends the oversized, tricklers, non-readers and garbage alone, its scene since issue 16); the
// slowloris peers come with a side port. The destructor closes every socket.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace sweepd::test {

// Which of the kinds a HostileDoors sends.
struct HostileKinds {
  bool silent = true, oversized = true, tricklers = true, non_readers = true, garbage = true,
       fuzzed = true, bad_tokens = true;
};

class HostileDoors {
 public:
  struct Doors {
    int tcp_port = 0;                   // 0: none
    std::filesystem::path unix_socket;  // empty: none
    int websocket_port = 0;             // 0: none
    int http_port = 0;                  // 0: no slowloris
  };

  HostileDoors(const Doors& doors, const std::string& token,
               std::span<const std::uint8_t> pose_frame, int per_kind, HostileKinds kinds = {});
  ~HostileDoors();
  HostileDoors(const HostileDoors&) = delete;
  HostileDoors& operator=(const HostileDoors&) = delete;

  // Connections opened so far (the bad tokens and slowloris peers keep opening new ones).
  std::size_t connections() const { return connections_; }

 private:
  enum class Door { kTcp, kUnix, kWebSocket };
  struct Peer {
    int socket;
    Door door;
  };

  // A connected socket to `door` (WebSocket: the upgrade sent), kept until the end.
  int open(Door door, int receive_buffer_bytes = 0);
  // `frame` to `socket`, as one binary message on WebSocket; never blocks.
  static void send(Door door, int socket, std::span<const std::uint8_t> frame);
  void attack(Door door, std::span<const std::uint8_t> pose_frame, int per_kind);
  // Every 100 ms: a byte to each trickler and slowloris peer, new bad-token Hellos.
  void pace(int per_kind);

  Doors doors_;
  HostileKinds kinds_;
  std::vector<std::uint8_t> hello_, bad_hello_;
  std::vector<int> sockets_;
  std::vector<Peer> tricklers_;
  std::vector<int> slowloris_;
  std::atomic<std::size_t> connections_ = 0;
  std::atomic<bool> pacing_ = true;
  std::thread pacer_;
};

}  // namespace sweepd::test

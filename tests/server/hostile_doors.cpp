#include "tests/server/hostile_doors.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <random>

#include "protocol/hostile_frames.h"
#include "protocol/messages.h"

namespace sweepd::test {
namespace {

using Bytes = std::vector<std::uint8_t>;

// MSG_DONTWAIT: an attacker whose buffers are full just stops; nothing here blocks on one.
// False when the peer is gone (or the buffer full).
bool send_all(int socket, std::span<const std::uint8_t> bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n =
        ::send(socket, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

// A TCP socket from 127.0.0.2 to 127.0.0.1:port.
int connect_from_elsewhere(int port, int receive_buffer_bytes) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (receive_buffer_bytes > 0)
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof(receive_buffer_bytes));
  sockaddr_in from{};
  from.sin_family = AF_INET;
  from.sin_addr.s_addr = htonl(0x7f000002);
  bind(fd, reinterpret_cast<const sockaddr*>(&from), sizeof(from));
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof(to));
  return fd;
}

// RFC 6455 5.2: the header of a client's binary message of `length` bytes — FIN, the mask bit
// and the length, the masking key 0 (so the payload goes as it is).
Bytes websocket_header(std::uint64_t length) {
  Bytes header = {0x82};
  if (length < 126) {
    header.push_back(static_cast<std::uint8_t>(0x80 | length));
  } else if (length <= 0xffff) {
    header.push_back(0x80 | 126);
    header.push_back(static_cast<std::uint8_t>(length >> 8));
    header.push_back(static_cast<std::uint8_t>(length));
  } else {
    header.push_back(0x80 | 127);
    for (int shift = 56; shift >= 0; shift -= 8)
      header.push_back(static_cast<std::uint8_t>(length >> shift));
  }
  header.resize(header.size() + 4, 0);
  return header;
}

Bytes hello(const std::string& token) {
  flatbuffers::FlatBufferBuilder builder;
  const std::span<const std::uint8_t> frame = protocol::build_hello(builder, token, "hostile");
  return {frame.begin(), frame.end()};
}

constexpr char kSlowHead[] = "GET /readyz HTTP/1.1\r\nHost: sweepd\r\nX-Slow: ";

}  // namespace

HostileDoors::HostileDoors(const Doors& doors, const std::string& token,
                           std::span<const std::uint8_t> pose_frame, int per_kind,
                           HostileKinds kinds)
    : doors_(doors), kinds_(kinds), hello_(hello(token)), bad_hello_(hello(token + "x")) {
  if (doors_.tcp_port > 0) attack(Door::kTcp, pose_frame, per_kind);
  if (!doors_.unix_socket.empty()) attack(Door::kUnix, pose_frame, per_kind);
  if (doors_.websocket_port > 0) attack(Door::kWebSocket, pose_frame, per_kind);
  pacer_ = std::thread([this, per_kind] { pace(per_kind); });
}

HostileDoors::~HostileDoors() {
  pacing_ = false;
  pacer_.join();
  for (int socket : sockets_) close(socket);
  for (int socket : slowloris_) close(socket);
}

int HostileDoors::open(Door door, int receive_buffer_bytes) {
  int fd = -1;
  if (door == Door::kUnix) {
    fd = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, doors_.unix_socket.c_str(), sizeof(address.sun_path) - 1);
    connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address));
  } else {
    fd = connect_from_elsewhere(door == Door::kTcp ? doors_.tcp_port : doors_.websocket_port,
                                receive_buffer_bytes);
  }
  if (door == Door::kWebSocket) {
    const std::string upgrade =
        "GET / HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(doors_.websocket_port) +
        "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
    send_all(fd, {reinterpret_cast<const std::uint8_t*>(upgrade.data()), upgrade.size()});
  }
  ++connections_;
  return fd;
}

void HostileDoors::send(Door door, int socket, std::span<const std::uint8_t> frame) {
  if (door == Door::kWebSocket) {
    Bytes message = websocket_header(frame.size());
    message.insert(message.end(), frame.begin(), frame.end());
    send_all(socket, message);
  } else {
    send_all(socket, frame);
  }
}

void HostileDoors::attack(Door door, std::span<const std::uint8_t> pose_frame, int per_kind) {
  const Bytes junk = protocol::garbage_frame();
  std::mt19937 random(49);  // the fuzzed frames: the same every run
  for (int i = 0; i < per_kind; ++i) {
    if (kinds_.silent) sockets_.push_back(open(door));
    if (kinds_.oversized) {
      const int oversized = open(door);
      send(door, oversized, protocol::length_prefix(1u << 20));
      sockets_.push_back(oversized);
    }
    if (kinds_.tricklers) {
      const int trickler = open(door);
      send(door, trickler, hello_);
      // The 16 MiB frame's prefix; on WebSocket inside a message that announces the whole
      // frame, whose bytes then follow as the trickle.
      const Bytes prefix = protocol::length_prefix(16u << 20);
      if (door == Door::kWebSocket) {
        Bytes header = websocket_header(4 + (16u << 20));
        header.insert(header.end(), prefix.begin(), prefix.end());
        send_all(trickler, header);
      } else {
        send_all(trickler, prefix);
      }
      sockets_.push_back(trickler);
      tricklers_.push_back({trickler, door});
    }
    if (kinds_.non_readers) {
      const int non_reader = open(door, 4096);
      send(door, non_reader, hello_);
      for (int p = 0; p < 40; ++p) send(door, non_reader, pose_frame);
      sockets_.push_back(non_reader);
    }
    if (kinds_.garbage) {
      const int garbage = open(door);
      send(door, garbage, hello_);
      for (int f = 0; f < 20; ++f) send(door, garbage, junk);
      sockets_.push_back(garbage);
    }
    if (kinds_.fuzzed) {
      const int fuzzed = open(door);
      send(door, fuzzed, hello_);
      for (int f = 0; f < 20; ++f) {
        Bytes frame(pose_frame.begin(), pose_frame.end());
        // The length prefix kept: each stays one frame, its body changed.
        const int changes = 1 + static_cast<int>(random() % 8);
        for (int c = 0; c < changes; ++c)
          frame[4 + random() % (frame.size() - 4)] = static_cast<std::uint8_t>(random());
        send(door, fuzzed, frame);
      }
      sockets_.push_back(fuzzed);
    }
  }
}

void HostileDoors::pace(int per_kind) {
  const std::uint8_t byte = 0x42;
  const std::span<const std::uint8_t> head(reinterpret_cast<const std::uint8_t*>(kSlowHead),
                                           sizeof(kSlowHead) - 1);
  while (pacing_) {
    for (const Peer& peer : tricklers_) send_all(peer.socket, {&byte, 1});
    if (doors_.http_port > 0) {
      // A slowloris peer the side port has cut is replaced by a new one.
      for (int& socket : slowloris_) {
        if (!send_all(socket, {&byte, 1})) {
          close(socket);
          socket = connect_from_elsewhere(doors_.http_port, 0);
          ++connections_;
          send_all(socket, head);
        }
      }
      while (slowloris_.size() < static_cast<std::size_t>(4 * per_kind)) {
        slowloris_.push_back(connect_from_elsewhere(doors_.http_port, 0));
        ++connections_;
        send_all(slowloris_.back(), head);
      }
    }
    for (const Door door : {Door::kTcp, Door::kWebSocket}) {
      if (!kinds_.bad_tokens) break;
      if ((door == Door::kTcp ? doors_.tcp_port : doors_.websocket_port) == 0) continue;
      for (int i = 0; i < per_kind; ++i) {
        const int guesser = open(door);
        send(door, guesser, bad_hello_);
        close(guesser);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

}  // namespace sweepd::test

#include "bench/hostile_peers.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>

#include "protocol/hostile_frames.h"
#include "protocol/messages.h"
#include "tests/server/loopback_port.h"

namespace sweepd::bench {
namespace {

void send_all(int socket, std::span<const std::uint8_t> bytes) {
  // MSG_DONTWAIT: an attacker whose buffers are full just stops; the bench never blocks on one.
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n =
        ::send(socket, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n <= 0) return;
    sent += static_cast<std::size_t>(n);
  }
}

}  // namespace

int HostilePeers::open(int receive_buffer_bytes) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (receive_buffer_bytes > 0)
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof(receive_buffer_bytes));
  const sockaddr_in address = test::loopback_address(port_);
  connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address));
  sockets_.push_back(fd);
  return fd;
}

HostilePeers::HostilePeers(int port, std::span<const std::uint8_t> pose_frame, int per_kind)
    : port_(port) {
  flatbuffers::FlatBufferBuilder builder;
  const std::span<const std::uint8_t> hello_frame = protocol::build_hello(builder, "", "hostile");
  const std::vector<std::uint8_t> hello(hello_frame.begin(), hello_frame.end());
  const std::vector<std::uint8_t> junk = protocol::garbage_frame();
  for (int i = 0; i < per_kind; ++i) {
    send_all(open(), protocol::length_prefix(1u << 20));
    const int trickler = open();
    send_all(trickler, hello);
    send_all(trickler, protocol::length_prefix(16u << 20));
    tricklers_.push_back(trickler);
    const int non_reader = open(4096);
    send_all(non_reader, hello);
    for (int p = 0; p < 40; ++p) send_all(non_reader, pose_frame);
    const int garbage = open();
    send_all(garbage, hello);
    for (int f = 0; f < 20; ++f) send_all(garbage, junk);
  }
  trickle_ = std::thread([this] {
    const std::uint8_t byte = 0x42;
    while (trickling_) {
      for (int socket : tricklers_) send_all(socket, {&byte, 1});
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
}

HostilePeers::~HostilePeers() {
  trickling_ = false;
  trickle_.join();
  for (int socket : sockets_) close(socket);
}

}  // namespace sweepd::bench

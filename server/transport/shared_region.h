// SharedRegion: memory sweepd shares with one Unix-socket client (MapSharedMemory, protocol
// 1.10) and writes pose replies into, so that a same-host client's 850 KB of positions do not
// cross the socket twice (copied in by the server, out by the client). The region is a memfd
// sealed at its size (F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) before its descriptor is sent:
// the client can map and write it but never shrink it under the server's writes (which would
// kill the server with SIGBUS). The server only writes it and reads nothing from it.
//
//   auto region = SharedRegion::create(bytes);   // std::system_error when the kernel refuses
//   region->fd()                                 // the descriptor to send (SCM_RIGHTS)
//   region->floats(offset, count)                // a span into it; nullopt when [offset,
//                                                // offset + 4 * count) is not inside or offset
//                                                // is not a multiple of 4
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

namespace sweepd::server {

class SharedRegion {
 public:
  static std::shared_ptr<SharedRegion> create(std::size_t bytes);
  SharedRegion(const SharedRegion&) = delete;
  SharedRegion& operator=(const SharedRegion&) = delete;
  ~SharedRegion();

  int fd() const { return fd_; }
  std::size_t size() const { return size_; }
  std::optional<std::span<float>> floats(std::uint64_t offset, std::size_t count) const;

 private:
  SharedRegion(int fd, void* memory, std::size_t size) : fd_(fd), memory_(memory), size_(size) {}

  int fd_;
  void* memory_;
  std::size_t size_;
};

}  // namespace sweepd::server

#include "server/transport/shared_region.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace sweepd::server {
namespace {

// Throws errno's error; `fd` (when ≥ 0) is closed first, errno kept across the close.
[[noreturn]] void fail(const char* what, int fd = -1) {
  const int error = errno;
  if (fd >= 0) close(fd);
  throw std::system_error(error, std::generic_category(), what);
}

}  // namespace

std::shared_ptr<SharedRegion> SharedRegion::create(std::size_t bytes) {
  const int fd = memfd_create("sweepd-shared-replies", MFD_CLOEXEC | MFD_ALLOW_SEALING);
  if (fd < 0) fail("memfd_create");
  if (ftruncate(fd, static_cast<off_t>(bytes)) != 0 ||
      fcntl(fd, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) != 0) {
    fail("sealing the shared region", fd);
  }
  void* memory = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (memory == MAP_FAILED) fail("mapping the shared region", fd);
  return std::shared_ptr<SharedRegion>(new SharedRegion(fd, memory, bytes));
}

SharedRegion::~SharedRegion() {
  munmap(memory_, size_);
  close(fd_);
}

std::optional<std::span<float>> SharedRegion::floats(std::uint64_t offset,
                                                     std::size_t count) const {
  if (offset % sizeof(float) != 0 || offset > size_ || count > (size_ - offset) / sizeof(float)) {
    return std::nullopt;
  }
  return std::span<float>(reinterpret_cast<float*>(static_cast<std::byte*>(memory_) + offset),
                          count);
}

}  // namespace sweepd::server

#include "server/models/store_edit_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sweepd::server {

StoreEditLock::StoreEditLock(const std::filesystem::path& lock_file)
    : descriptor_(::open(lock_file.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0644)) {
  if (descriptor_ < 0) {
    throw std::runtime_error("cannot create the edit lock " + lock_file.string() + ": " +
                             std::strerror(errno));
  }
  while (::flock(descriptor_, LOCK_EX) != 0) {
    if (errno == EINTR) continue;
    const int error = errno;
    ::close(descriptor_);
    throw std::runtime_error("cannot lock " + lock_file.string() + ": " + std::strerror(error));
  }
}

StoreEditLock::~StoreEditLock() { ::close(descriptor_); }  // closing releases the lock

}  // namespace sweepd::server

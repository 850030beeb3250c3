#include "server/models/binding_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "io/files/load_error.h"

namespace sweepd::server {
namespace {

BindingFile::Version version_of(const struct stat& status) {
  return {status.st_dev, status.st_ino, status.st_size,
          static_cast<std::int64_t>(status.st_mtim.tv_sec) * 1'000'000'000 +
              status.st_mtim.tv_nsec};
}

}  // namespace

std::shared_ptr<const BindingFile> BindingFile::open(const std::filesystem::path& file) {
  const int descriptor = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor < 0)
    throw io::LoadError(file, std::string("cannot open the file: ") + std::strerror(errno));
  struct stat status {};
  if (::fstat(descriptor, &status) != 0) {
    const int error = errno;
    ::close(descriptor);
    throw io::LoadError(file, std::string("cannot stat the file: ") + std::strerror(error));
  }
  return std::shared_ptr<const BindingFile>(new BindingFile(file, descriptor, version_of(status)));
}

BindingFile::~BindingFile() { ::close(descriptor_); }

std::vector<std::uint8_t> BindingFile::bytes() const {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(version_.size));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t read = ::pread(descriptor_, bytes.data() + done, bytes.size() - done,
                                 static_cast<off_t>(done));
    if (read < 0 && errno == EINTR) continue;
    if (read < 0) throw io::LoadError(path_, std::string("cannot read: ") + std::strerror(errno));
    if (read == 0) break;  // shorter than it was: the decoder reports the truncation
    done += static_cast<std::size_t>(read);
  }
  bytes.resize(done);
  return bytes;
}

bool BindingFile::replaced() const {
  struct stat status {};
  if (::stat(path_.c_str(), &status) != 0) return false;
  return !(version_of(status) == version_);
}

}  // namespace sweepd::server

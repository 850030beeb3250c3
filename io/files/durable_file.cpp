#include "io/files/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sweepd::io {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const char* step, int error) {
  throw std::runtime_error("cannot write " + file.string() + " (" + step + ": " +
                           std::strerror(error) + ")");
}

// Closes fd and throws for `step`, with the errno of the step (close may change errno).
[[noreturn]] void close_and_fail(int fd, const std::filesystem::path& file, const char* step) {
  const int error = errno;
  ::close(fd);
  fail(file, step, error);
}

}  // namespace

void write_file_durably(const std::filesystem::path& file, std::span<const std::uint8_t> bytes) {
  const std::filesystem::path temporary = file.string() + "." + std::to_string(::getpid()) + "@" +
                                          this_host() + std::string(kTemporarySuffix);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(temporary, "open", errno);
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) close_and_fail(fd, temporary, "write");
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) close_and_fail(fd, temporary, "fsync");
  if (::close(fd) != 0) fail(temporary, "close", errno);
  if (::rename(temporary.c_str(), file.c_str()) != 0) fail(file, "rename", errno);
  sync_directory(file.has_parent_path() ? file.parent_path() : std::filesystem::path("."));
}

std::string this_host() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "localhost";
  std::string host(name);
  std::replace(host.begin(), host.end(), '/', '_');  // never a path separator in a file name
  return host;
}

TemporaryWriter temporary_writer(const std::filesystem::path& file) {
  std::string name = file.filename().string();
  if (!name.ends_with(kTemporarySuffix)) return {};
  name.resize(name.size() - kTemporarySuffix.size());
  const std::size_t at = name.rfind('@');
  const std::size_t dot = name.rfind('.', at);
  if (at == std::string::npos || dot == std::string::npos || dot + 1 == at) return {};
  const std::string digits = name.substr(dot + 1, at - dot - 1);
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
      digits.size() > 9)
    return {};
  return {std::stol(digits), name.substr(at + 1)};
}

void sync_directory(const std::filesystem::path& directory) {
  const int directory_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (directory_fd >= 0) {
    ::fsync(directory_fd);
    ::close(directory_fd);
  }
}

}  // namespace sweepd::io

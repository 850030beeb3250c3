// NotifySocket: a fake systemd notify socket for tests — a Unix datagram socket bound at `path`
// that receives what sd_notify(3) sends (NOTIFY_SOCKET=path). receive(timeout): the next
// datagram's text ("READY=1\nSTATUS=accepting"), nullopt when none came in time. Each message
// also carries the time it was taken off the socket (steady clock).
// NotifyEnvironment(socket, watchdog_usec, watchdog_pid): sets NOTIFY_SOCKET (and WATCHDOG_USEC,
// WATCHDOG_PID when given) in this process — and so in the daemons it starts — as systemd
// would, and clears them when it goes.
#pragma once

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

namespace sweepd::test {

struct NotifyMessage {
  std::string text;
  std::chrono::steady_clock::time_point received;
};

class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path) : path_(path) {
    std::filesystem::remove(path);
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
    bound_ = bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
  }
  ~NotifySocket() {
    close(fd_);
    std::filesystem::remove(path_);
  }
  NotifySocket(const NotifySocket&) = delete;
  NotifySocket& operator=(const NotifySocket&) = delete;

  bool bound() const { return bound_; }
  const std::filesystem::path& path() const { return path_; }

  std::optional<NotifyMessage> receive(std::chrono::milliseconds timeout) {
    pollfd ready{fd_, POLLIN, 0};
    if (poll(&ready, 1, static_cast<int>(timeout.count())) != 1) return std::nullopt;
    char buffer[4096];
    const ssize_t n = recv(fd_, buffer, sizeof(buffer), 0);
    if (n < 0) return std::nullopt;
    return NotifyMessage{std::string(buffer, static_cast<std::size_t>(n)),
                         std::chrono::steady_clock::now()};
  }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  bool bound_ = false;
};

class NotifyEnvironment {
 public:
  NotifyEnvironment(const std::filesystem::path& socket, const char* watchdog_usec = nullptr,
                    const char* watchdog_pid = nullptr) {
    setenv("NOTIFY_SOCKET", socket.c_str(), 1);
    if (watchdog_usec) setenv("WATCHDOG_USEC", watchdog_usec, 1);
    if (watchdog_pid) setenv("WATCHDOG_PID", watchdog_pid, 1);
  }
  ~NotifyEnvironment() {
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
    unsetenv("WATCHDOG_PID");
  }
};

}  // namespace sweepd::test

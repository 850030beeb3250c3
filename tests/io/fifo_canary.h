// FifoCanary: a named pipe (FIFO) put where a loader must not look, which tells whether anyone
// opened it for reading while some work ran.
//
// Why a FIFO: nobody ever writes to it, so an ordinary open for reading (fopen, ifstream,
// tinygltf's own FileExists) blocks until a writer comes; the opener cannot have come and gone
// unseen. While `work` runs, a watcher thread tries every millisecond to open the write end
// with O_NONBLOCK, which the kernel grants only when some process has the pipe open (or is
// blocked opening it) for reading. When that happens the canary counts it and closes its end
// at once, so the reader sees end of file and the work finishes instead of hanging the test.
// A stat() does not open and is not seen here (the daemon test's strace run sees those).
//
//   FifoCanary canary(dir / "canary");        // mkfifo; removed by the destructor
//   bool opened = canary.opened_during([&] { load(...); });
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <thread>

namespace sweepd::io::testing {

class FifoCanary {
 public:
  explicit FifoCanary(std::filesystem::path path) : path_(std::move(path)) {
    std::filesystem::remove(path_);
    created_ = ::mkfifo(path_.c_str(), 0644) == 0;
  }
  ~FifoCanary() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  FifoCanary(const FifoCanary&) = delete;
  FifoCanary& operator=(const FifoCanary&) = delete;

  bool created() const { return created_; }
  const std::filesystem::path& path() const { return path_; }

  // Runs `work` on this thread; true when the canary was opened for reading meanwhile.
  bool opened_during(const std::function<void()>& work) {
    std::atomic<bool> done{false}, opened{false};
    std::thread watcher([&] {
      while (!done) {
        const int fd = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK);
        if (fd >= 0) {
          opened = true;
          ::close(fd);  // the reader gets end of file and carries on
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
    work();
    done = true;
    watcher.join();
    return opened;
  }

 private:
  std::filesystem::path path_;
  bool created_ = false;
};

}  // namespace sweepd::io::testing

#include "server/watchdog_pinger.h"

#include <condition_variable>
#include <mutex>

#include "server/log_event.h"

namespace sweepd::server {

WatchdogPinger::WatchdogPinger(SystemdNotifier& notifier, std::chrono::microseconds timeout,
                               AliveProbe alive) {
  const auto period = std::max(std::chrono::milliseconds(1),
                               std::chrono::duration_cast<std::chrono::milliseconds>(timeout / 2));
  thread_ = std::jthread([&notifier, period, alive = std::move(alive)](std::stop_token stop) {
    std::mutex mutex;
    std::condition_variable_any wake;
    while (!stop.stop_requested()) {
      const auto deadline = std::chrono::steady_clock::now() + period;
      if (alive(period)) {
        notifier.watchdog_ping();
      } else if (std::chrono::steady_clock::now() >= deadline) {
        // No answer within the period (a probe that declines at once, before the server
        // serves or after it stopped, is not a miss).
        log_event("watchdog_probe_missed", {{"waited_ms", period.count()}});
      }
      std::unique_lock lock(mutex);
      wake.wait_until(lock, stop, deadline, [] { return false; });
    }
  });
}

WatchdogPinger::~WatchdogPinger() {
  thread_.request_stop();
  thread_.join();
}

}  // namespace sweepd::server

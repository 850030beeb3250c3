#include "server/systemd_notifier.h"

#include <systemd/sd-daemon.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "server/log_event.h"

namespace sweepd::server {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  enabled_ = socket != nullptr && *socket != '\0';
  std::uint64_t microseconds = 0;
  // > 0: WATCHDOG_USEC is set and WATCHDOG_PID is unset or this process.
  if (enabled_ && sd_watchdog_enabled(0, &microseconds) > 0 && microseconds > 0) {
    watchdog_timeout_ = std::chrono::microseconds(microseconds);
  }
}

void SystemdNotifier::stage(Readiness::Stage stage) {
  std::string message = std::string("STATUS=") + Readiness::describe(stage);
  if (stage == Readiness::Stage::kAccepting) message = "READY=1\n" + message;
  if (stage == Readiness::Stage::kDraining) message = "STOPPING=1\n" + message;
  send(message);
}

void SystemdNotifier::status(std::string_view text) { send("STATUS=" + std::string(text)); }

void SystemdNotifier::watchdog_ping() { send("WATCHDOG=1"); }

void SystemdNotifier::send(const std::string& message) {
  if (!enabled_) return;
  const int result = sd_notify(0, message.c_str());
  if (result < 0 && !failure_logged_.exchange(true)) {
    log_event("sd_notify_failed", {{"socket", std::getenv("NOTIFY_SOCKET")},
                                   {"message", message},
                                   {"reason", std::strerror(-result)}});
  }
}

}  // namespace sweepd::server

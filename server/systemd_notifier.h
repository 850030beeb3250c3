// SystemdNotifier: sweepd's side of systemd's notify protocol (sd_notify(3), Debian's
// libsystemd), for a unit of Type=notify with WatchdogSec= (deploy/sweepd.service).
//
// Reads NOTIFY_SOCKET and WATCHDOG_USEC (WATCHDOG_PID, when set, must be this process) once, at
// construction. Without NOTIFY_SOCKET every call is a no-op and the daemon runs as it always
// has. Thread-safe (each message is one datagram sd_notify sends on a socket of its own).
// stage(s): the stage as STATUS=<Readiness::describe>; with READY=1 for accepting (the moment
//   /readyz turns 200) and STOPPING=1 for draining (SIGTERM).
// status(text): STATUS=text (e.g. a fatal start-up error, shown by `systemctl status`).
// watchdog_ping(): WATCHDOG=1.
// watchdog_timeout(): WATCHDOG_USEC when systemd asks for pings, else nullopt.
// A message systemd does not take (socket gone, refused) is logged once as sd_notify_failed.
#pragma once

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <string_view>

#include "server/readiness.h"

namespace sweepd::server {

class SystemdNotifier {
 public:
  SystemdNotifier();

  bool enabled() const { return enabled_; }
  std::optional<std::chrono::microseconds> watchdog_timeout() const { return watchdog_timeout_; }

  void stage(Readiness::Stage stage);
  void status(std::string_view text);
  void watchdog_ping();

 private:
  void send(const std::string& message);

  bool enabled_ = false;
  std::optional<std::chrono::microseconds> watchdog_timeout_;
  std::atomic<bool> failure_logged_{false};
};

}  // namespace sweepd::server

// WatchdogPinger: systemd's watchdog (WatchdogSec=) fed only while the server is alive — a
// thread that, every half of the watchdog timeout, asks `alive(wait)` and sends WATCHDOG=1
// (SystemdNotifier::watchdog_ping) only when it answers true within that half.
//
// sweepd's `alive` posts a job to the protocol's I/O thread and waits for it (Server::snapshot),
// so a wedged I/O thread stops the pings and systemd restarts the daemon after WatchdogSec;
// a probe that is not answered within the period is logged (watchdog_probe_missed). Before
// the I/O thread runs (the store restored, the default model bound) the probe declines at once
// and nothing is sent: systemd arms the watchdog only at READY=1. Stops and joins in the
// destructor; the notifier and `alive`'s captures must outlive it.
#pragma once

#include <chrono>
#include <functional>
#include <thread>

#include "server/systemd_notifier.h"

namespace sweepd::server {

class WatchdogPinger {
 public:
  using AliveProbe = std::function<bool(std::chrono::milliseconds wait)>;

  WatchdogPinger(SystemdNotifier& notifier, std::chrono::microseconds timeout, AliveProbe alive);
  ~WatchdogPinger();
  WatchdogPinger(const WatchdogPinger&) = delete;
  WatchdogPinger& operator=(const WatchdogPinger&) = delete;

 private:
  std::jthread thread_;
};

}  // namespace sweepd::server

#include "client/reconnect.h"

#include <chrono>
#include <thread>

namespace sweepd::client {

std::unique_ptr<Connection> reconnect(const std::string& address, const ClientTls& tls,
                                      const std::function<void(Connection&)>& set_up) {
  std::chrono::milliseconds pause(200);
  for (int tries = 1;; ++tries) {
    try {
      auto connection = std::make_unique<Connection>(address, tls);
      set_up(*connection);
      return connection;
    } catch (const ConnectionLost&) {
      if (tries == kReconnectTries) throw;
    }
    std::this_thread::sleep_for(pause);
    pause *= 2;
  }
}

}  // namespace sweepd::client

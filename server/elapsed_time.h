// nanoseconds_since: the steady clock's time since `start`, in nanoseconds, as the daemon's
// logs, latencies and replies count it.
#pragma once

#include <chrono>
#include <cstdint>

namespace sweepd::server {

inline std::uint64_t nanoseconds_since(std::chrono::steady_clock::time_point start) {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start)
          .count());
}

}  // namespace sweepd::server

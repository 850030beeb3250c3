// What the hostile-client tests send and look for, on TCP and WebSocket alike: a bare length
// prefix (a frame announced, its body never or slowly sent), the daemon's JSON log lines of an
// event, and the last Error a client reads before the server closes the connection.
#pragma once

#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/server/daemon_process.h"

namespace sweepd::test {

inline std::vector<std::uint8_t> length_prefix(std::uint32_t length) {
  return {static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8),
          static_cast<std::uint8_t>(length >> 16), static_cast<std::uint8_t>(length >> 24)};
}

// Log lines of `event` (the daemon logs one JSON object per line) that contain `part`.
inline std::size_t log_lines(const std::string& log, const std::string& event,
                             const std::string& part) {
  std::istringstream lines(log);
  std::size_t n = 0;
  for (std::string line; std::getline(lines, line);)
    if (line.find("\"" + event + "\"") != std::string::npos && line.find(part) != std::string::npos)
      ++n;
  return n;
}

// Reads until the server closes the connection; the last Error seen, if any.
inline std::optional<protocol::ErrorCode> last_error_before_close(FrameClient& client) {
  std::optional<protocol::ErrorCode> last;
  while (const protocol::Message* message = client.receive()) {
    if (const protocol::Error* error = message->body_as_Error()) {
      last = error->code();
      if (error->fatal()) {
        EXPECT_TRUE(client.closed_by_server());
        return last;
      }
    }
  }
  return last;
}

}  // namespace sweepd::test

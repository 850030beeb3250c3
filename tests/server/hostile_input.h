// What the hostile-client tests send and look for, on TCP and WebSocket alike: a bare length
// prefix and a garbage frame (protocol/hostile_frames.h), the daemon's JSON log lines of an
// event, the last Error a client reads before the server closes the connection, and a frame
// past the shared buffer budget.
#pragma once

#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "protocol/hostile_frames.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {

using protocol::garbage_frame;
using protocol::length_prefix;

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

// On a daemon with --max-buffered-bytes 1 MiB, after Hello: a frame of 2 MiB (within
// max_frame_bytes, past the budget all connections share) gets ResourceExhausted, not fatal,
// and the session goes on: the next pose (the mannequin's 31 joints) is answered.
inline void expect_frame_past_budget_refused(FrameClient& client, std::uint32_t model_id) {
  std::vector<std::uint8_t> frame = length_prefix(2u << 20);
  frame.resize(4 + (2u << 20), 0x33);
  ASSERT_TRUE(client.send_bytes(frame));
  const protocol::Error* error = client.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::ResourceExhausted);
  EXPECT_FALSE(error->fatal());
  EXPECT_NE(error->message()->str().find("2097152"), std::string::npos) << error->message()->str();
  const std::vector<protocol::Quat> wire = to_wire(bent_rotations(31));
  ASSERT_TRUE(send_pose(client, pose_fields(model_id, 7, wire)));
  const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->sequence(), 7u);
}

}  // namespace sweepd::test
